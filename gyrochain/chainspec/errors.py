"""The one error a user sees: ``SpecError(field, why)`` prints as ``field: why``.  Every command
turns its users' mistakes (a spec field, an option, a parameter value, a file) into one; the command
line prints it as one line ``error: field: why`` and exits with status 2."""
from __future__ import annotations

import difflib


class SpecError(ValueError):
    """A malformed input: ``field`` names the offending entry (``body[2].A``, ``--param m2``)."""

    def __init__(self, field_name: str, message: str):
        super().__init__(f"{field_name}: {message}")
        self.field = field_name
        self.message = message


def did_you_mean(word: str, choices) -> str:
    """"did you mean X? " for the choice nearest to a mistyped word, "" when none is near."""
    near = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1)
    return f"did you mean {near[0]}? " if near else ""
