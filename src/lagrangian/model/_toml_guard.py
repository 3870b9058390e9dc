"""The nesting of a TOML text, checked before the TOML reader sees it.

`tomllib` reads arrays and inline tables recursively: ``a = [[[ ... ]]]`` nested 500
deep (a 1 KB file) ends in a `RecursionError` inside it.  `check_nesting` scans the
text once (strings and comments skipped) and refuses a file nested deeper than
`MAX_NESTING`, naming the line where the limit is passed.  A model file needs 3 levels
at most (an inertia matrix in an inline table).
"""

from __future__ import annotations

import re

from ..errors import ModelError

__all__ = ["MAX_NESTING", "check_nesting"]

#: Deepest nesting of arrays and inline tables accepted (table headers count one).
MAX_NESTING = 32

_INTERESTING = re.compile(r"[\[\]{}\"'#\n]")
_BASIC = re.compile(r'(?:[^"\\\n]|\\.)*"')  # the rest of a one-line basic string, to its quote
_BASIC_MULTI = re.compile(r'(?:[^"\\]|\\.|"(?!""))*"""', re.DOTALL)


def check_nesting(text: str, source: str | None) -> None:
    """Raise `ModelError` when arrays and inline tables in ``text`` nest deeper than `MAX_NESTING`.

    Text that is not valid TOML is left to the TOML reader, which says what is wrong.

    Parameters
    ----------
    text : str
        A TOML text.
    source : str or None
        Names the text in error messages.
    """
    depth, line, pos = 0, 1, 0
    while True:
        match = _INTERESTING.search(text, pos)
        if match is None:
            return
        char, pos = match.group(), match.end()
        if char == "\n":
            line += 1
        elif char == "#":
            end = text.find("\n", pos)
            if end < 0:
                return
            pos = end
        elif char in "\"'":
            end = _string_end(text, pos, char)
            if end < 0:
                return  # an unterminated string: the TOML reader reports it
            line += text.count("\n", pos, end)
            pos = end
        elif char in "[{":
            depth += 1
            if depth > MAX_NESTING:
                lines = text.splitlines()
                raise ModelError(
                    f"arrays and tables are nested more than {MAX_NESTING} deep here",
                    file=source, line=line, column=pos - (text.rfind("\n", 0, pos) + 1),
                    source_line=lines[line - 1][:200] if line <= len(lines) else None,
                    fix="a model file needs a few levels at most (e.g. the rows of an inertia matrix); "
                    "remove the extra brackets",
                )
        else:
            depth = max(0, depth - 1)


def _string_end(text: str, pos: int, quote: str) -> int:
    """The index just past the string opened by ``quote`` at ``pos - 1``, or -1 when it is not closed."""
    if text.startswith(quote * 2, pos):  # a multi-line string, or an empty one
        if not text.startswith(quote * 3, pos - 1):
            return pos + 1  # "" or ''
        start = pos + 2
        if quote == "'":
            end = text.find("'''", start)
            return -1 if end < 0 else _past_quotes(text, end + 3, quote)
        match = _BASIC_MULTI.match(text, start)
        return -1 if match is None else _past_quotes(text, match.end(), quote)
    if quote == "'":
        end = text.find("'", pos)
        newline = text.find("\n", pos)
        return -1 if end < 0 or 0 <= newline < end else end + 1
    match = _BASIC.match(text, pos)
    return -1 if match is None else match.end()


def _past_quotes(text: str, pos: int, quote: str) -> int:
    """A multi-line string may end with up to two more quotes (``""""a""""`` is valid TOML)."""
    for _ in range(2):
        if text.startswith(quote, pos):
            pos += 1
    return pos
