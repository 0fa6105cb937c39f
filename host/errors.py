"""Errors meant for people: one clear line, an exit status, no traceback."""
from __future__ import annotations


class UserError(Exception):
    """Bad input from the user (a profile, a file, an argument). `issv` prints it and exits."""

    status = 1


class ProfileError(UserError):
    """A profile failed validation; each line names the file, the key path, expected and found."""

    status = 2

    def __init__(self, lines: list[str]) -> None:
        super().__init__("\n".join(lines))
        self.lines = lines
