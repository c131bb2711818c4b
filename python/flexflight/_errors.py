"""The exception and diagnostic types of flexflight (shared by the native module)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, List, Optional

__all__ = ["Diagnostic", "Error"]


@dataclass(frozen=True)
class Diagnostic:
    """One diagnostic of the checker or of an operation.

    Attributes:
        code: the stable code (e.g. ``vdl::unit::mismatch``), documented in
            ``docs/diagnostic-codes.md``.
        message: what is wrong.
        severity: ``"error"`` or ``"warning"``.
        file: the file of the primary label (``None`` when the diagnostic has no location).
        line: 1-based line of the primary label.
        column: 1-based column of the primary label.
        help: how to fix it, when known.
        labels: every label, as dicts with ``file``, ``line``, ``column``, ``end_line``,
            ``end_column`` and ``message``.
    """

    code: str
    message: str
    severity: str = "error"
    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None
    help: Optional[str] = None
    labels: List[dict] = field(default_factory=list, compare=False)

    @classmethod
    def _from_json(cls, d: dict) -> "Diagnostic":
        return cls(
            code=d.get("code", ""),
            message=d.get("message", ""),
            severity=str(d.get("severity", "error")).lower(),
            file=d.get("file"),
            line=d.get("line"),
            column=d.get("column"),
            help=d.get("help"),
            labels=list(d.get("labels") or []),
        )

    @property
    def is_error(self) -> bool:
        """Whether this diagnostic is an error (the input cannot be used)."""
        return self.severity == "error"

    def __str__(self) -> str:
        where = ""
        if self.file is not None:
            where = f"{self.file}:{self.line}:{self.column}: "
        text = f"{where}{self.severity}[{self.code}]: {self.message}"
        if self.help:
            text += f"\n  help: {self.help}"
        return text


class Error(Exception):
    """An operation of flexflight failed.

    Attributes:
        message: what failed.
        code: the first diagnostic's code, or ``"usage"`` for a request that cannot be met
            as asked (an unknown scenario name, a missing file, a bad option), or a stable
            code such as ``run::cannot_start``.
        diagnostics: the diagnostics (``Diagnostic``), each with file, line and column when
            the input is at fault; empty for a usage error.
        file, line, column, help: those of the first diagnostic (``None`` without one).
    """

    def __init__(self, message: str, code: Optional[str] = None,
                 diagnostics: Optional[List[Diagnostic]] = None) -> None:
        self.message = message
        self.code = code
        self.diagnostics: List[Diagnostic] = list(diagnostics or [])
        first = self.diagnostics[0] if self.diagnostics else None
        self.file = first.file if first else None
        self.line = first.line if first else None
        self.column = first.column if first else None
        self.help = first.help if first else None
        super().__init__(self._text())

    def _text(self) -> str:
        if not self.diagnostics:
            return f"[{self.code}] {self.message}" if self.code else self.message
        return "\n".join(str(d) for d in self.diagnostics)


def _from_native(message: str, code: Optional[str], diagnostics: Any) -> Error:
    """Builds the exception the native module raises."""
    return Error(message, code, [Diagnostic._from_json(d) for d in diagnostics or []])
