"""Errors raised for bad input, before any computation."""


class InputError(ValueError):
    """Bad input.  ``field`` names the offending setting (a dotted path)."""

    def __init__(self, field, reason):
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")
