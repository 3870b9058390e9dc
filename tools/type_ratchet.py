"""Hold the number of mypy errors on ``src/`` at or below the number in ``tools/mypy_baseline.txt``.

Run by ``make types``.  mypy reads its settings from ``[tool.mypy]`` in pyproject.toml.  The
count may only fall: when it rises the script fails and lists the errors; when it falls it
says so, and asks to lower the stored number to the new count (in the same commit as the fix),
so that the errors fixed cannot come back unnoticed.

Usage: ``python tools/type_ratchet.py [--update] [mypy arguments...]``; ``--update`` writes the
current count to the baseline file (only when it is lower, unless ``--force`` is given too).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BASELINE = ROOT / "tools" / "mypy_baseline.txt"
#: mypy's closing line: "Found 12 errors in 3 files (checked 242 source files)" or "Success: no issues found ...".
_FOUND = re.compile(r"^Found (\d+) errors? in \d+ files?", re.MULTILINE)
_SUCCESS = re.compile(r"^Success: no issues found", re.MULTILINE)


def read_baseline(path: Path = BASELINE) -> int:
    """The allowed number of errors: the first line of ``path`` that is not a comment."""
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            return int(line)
    raise ValueError(f"{path} holds no error count")


def count_errors(output: str) -> int | None:
    """The error count of mypy's ``output``, or None when mypy did not finish its check."""
    if _SUCCESS.search(output):
        return 0
    found = _FOUND.search(output)
    return int(found.group(1)) if found else None


def run_mypy(arguments: list[str]) -> tuple[int | None, str]:
    """Run mypy (on the files of ``[tool.mypy]``) in the project root; (error count, its output)."""
    done = subprocess.run([sys.executable, "-m", "mypy", *arguments], cwd=ROOT, capture_output=True,
                          text=True, check=False)
    output = done.stdout + done.stderr
    return count_errors(output), output


def main(argv: list[str]) -> int:
    update = "--update" in argv
    force = "--force" in argv
    arguments = [a for a in argv if a not in ("--update", "--force")]
    allowed = read_baseline()
    count, output = run_mypy(arguments)
    if count is None:
        sys.stdout.write(output)
        print("type ratchet: mypy did not report a count (see its output above)", file=sys.stderr)
        return 2
    if update and (count < allowed or force):
        text = BASELINE.read_text(encoding="utf-8")
        BASELINE.write_text(re.sub(r"^\d+$", str(count), text, count=1, flags=re.MULTILINE), encoding="utf-8")
        print(f"type ratchet: {BASELINE.relative_to(ROOT)} lowered from {allowed} to {count}")
        return 0
    if count > allowed:
        sys.stdout.write(output)
        print(f"type ratchet: mypy reports {count} errors, more than the {allowed} allowed in "
              f"{BASELINE.relative_to(ROOT)}; fix the new ones (an annotation or a guard, not a `# type: ignore`)",
              file=sys.stderr)
        return 1
    if count < allowed:
        print(f"type ratchet: {count} errors, fewer than the {allowed} allowed: lower the number in "
              f"{BASELINE.relative_to(ROOT)} to {count} (`python tools/type_ratchet.py --update`)")
        return 0
    print(f"type ratchet: {count} errors, as allowed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
