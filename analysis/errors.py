"""Errors raised for bad survey input.

Every error carries one line of text that names the file and the place (row,
column or key) and says what is wrong; the command line prints it as
``error: <text>`` and exits with status 2.
"""
from __future__ import annotations


class SurveyInputError(Exception):
    """Bad input: a file, row, column or key that cannot be used.

    Parameters
    ----------
    message : str
        What is wrong, without the file name.
    file : str, optional
        The file the problem was found in.
    row : int, optional
        1-based row as a spreadsheet shows it (the header is row 1).
    column : str, optional
        Column header (or key) the problem was found in.
    """

    def __init__(self, message: str, file: str | None = None,
                 row: int | None = None, column: str | None = None):
        self.message = message
        self.file = file
        self.row = row
        self.column = column
        super().__init__(self.line())

    def line(self) -> str:
        """The one-line description ``<file>: row R, column 'C': <what>``."""
        where = []
        if self.row is not None:
            where.append(f"row {self.row}")
        if self.column is not None:
            where.append(f"column {self.column!r}")
        head = ", ".join(where)
        parts = [p for p in (self.file, head) if p]
        prefix = ": ".join(parts)
        return f"{prefix}: {self.message}" if prefix else self.message

    def with_file(self, file: str) -> "SurveyInputError":
        """Return a copy that names ``file`` (when it did not name one)."""
        if self.file:
            return self
        return SurveyInputError(self.message, file, self.row, self.column)
