"""Errors raised for bad input, before any computation."""
import math
import sys


class InputError(ValueError):
    """Bad input.  ``field`` names the offending setting (a dotted path)."""

    def __init__(self, field, reason):
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")


def check_finite(value, path=""):
    """Refuses a NaN or an infinity anywhere in ``value`` (nested mappings
    and lists, as read from YAML), and an integer too large for a float,
    naming it by its dotted path (``path``: that of ``value`` itself)."""
    if isinstance(value, float) and not math.isfinite(value):
        raise InputError(path or "value", f"must be a finite number, got {value}")
    if isinstance(value, int) and abs(value) > sys.float_info.max:
        raise InputError(path or "value", f"must be a finite number, got an integer of {len(str(abs(value)))} digits")
    if isinstance(value, dict):
        for k, v in value.items():
            check_finite(v, f"{path}.{k}" if path else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            check_finite(v, f"{path}.{i}" if path else str(i))
    return value
