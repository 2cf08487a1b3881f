"""Choosing an implementation when a kernel is compiled.

numba types and compiles both sides of a branch on a literal argument
(LLVM drops the dead side afterwards, but only after numba has typed and
lowered it).  The dispatchers of the zone law, the joint law and the
block kind are therefore ``numba.extending.overload``s that pick one
implementation from a table by the literal value of an argument while
the caller is being typed: a model compiles only the laws and the block
kind it uses.
"""
from numba.core import types
from numba.core.errors import TypingError


def literal(key, what):
    """The literal value of the numba type ``key``; refused (at compile
    time) unless ``key`` is a literal (an argument that step.specialised
    compiles as one, or a constant)."""
    if not isinstance(key, types.Literal):
        raise TypingError(f"{what} must be a compile-time literal, got {key}")
    return key.literal_value


def choose(table, key, what):
    """table[literal value of the numba type ``key``] (``literal``)."""
    return table[literal(key, what)]
