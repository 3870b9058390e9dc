"""``lagrangian`` command line: one error boundary, nothing below it prints or exits.

Each command's arguments are declared in ``cli/_arguments/<command>.py`` (a ``SUMMARY`` line
and ``register(subparsers)``), which imports nothing of the pipeline, so that ``--help`` and
the parsing cost milliseconds; its work is the ``run`` of ``cli/_<command>.py``, imported when
the command runs: ``run(args) -> str | bytes | None`` returns what goes to standard output, or
to ``-o FILE`` (written atomically) when the command has that option; commands that write
their own files return a short summary.

Exit codes: 0 success, 1 usage error (argparse), 2 bad model or derivation error,
3 output file (or standard output: a full device) could not be written, 4 simulation could
not start or go on, 5 a cross-check (Newton–Euler against Lagrange) failed, 130 interrupted
by Ctrl-C (also while the package is still loading; `optimize` writes the solver's last iterate), 141 standard output closed by its
reader (``| head``).
"""

from __future__ import annotations

import argparse
import atexit
import importlib
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from .. import __version__
from ..errors import EnsembleInterrupted, Interrupted, LagrangianError, ModelError, OutputError
from ._atomic import check_output, write_output

__all__ = ["entrypoint", "main"]

# The commands, in the order `--help` lists them; each name is a module `cli/_arguments/<name>.py`
# (its arguments) and a module `cli/_<name>.py` (its work).
COMMANDS = ("derive", "simulate", "view", "sweep", "verify", "analyse", "equilibria", "linearize", "modes", "lqr",
            "optimize", "identify", "report", "export")


def _commands() -> list:
    return [importlib.import_module(f"{__package__}._arguments.{name}") for name in COMMANDS]


def _parser(only: str | None = None) -> argparse.ArgumentParser:
    """The whole parser; with ``only`` (a command's name), the parser of that command alone under it.

    A command line that starts with a command's name needs no other command's parser (their options
    are a hundred ``add_argument`` calls); ``lagrangian --help`` lists every command.
    """
    modules = _commands()
    listing = "\n".join(
        f"  {name:<10} " + module.SUMMARY.replace("\n", "\n" + " " * 13) for name, module in zip(COMMANDS, modules, strict=True)
    )
    description = (
        "Lagrange's equations of a mechanical system, derived the way the course does it:\n"
        "principal parameters, virtual velocity field, T and U, generalized forces by virtual\n"
        "power, the n Lagrange equations, first integrals, and M(q,t) q'' = F(q,q',t).\n\n"
        f"commands:\n{listing}\n\n"
        "Run `lagrangian COMMAND --help` for its options. Model file format: docs/model-format.md."
    )
    parser = argparse.ArgumentParser(prog="lagrangian", description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"lagrangian {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, module in zip(COMMANDS, modules, strict=True):
        if only is None or name == only:
            module.register(sub)
    return parser


def format_error(error: LagrangianError) -> str:
    """The message a user sees: ``file:line:col: error: ...``, the source line with a caret, a tip."""
    if isinstance(error, ModelError):
        where = error.location
        message = _capped(error.message)
        lines = [f"{where}: error: {message}" if where else f"error: {message}"]
        if error.file and error.line:
            try:
                source = Path(error.file).read_text(encoding="utf-8").splitlines()[error.line - 1]
                column = error.column if error.column and 0 < error.column <= len(source) + 1 else None
                source, column = _window(source, column)
                gutter = f"  {error.line} | "
                lines.append(gutter + source)
                if column:
                    lines.append(" " * (len(gutter) + column - 1) + "^")
            except (OSError, IndexError, UnicodeDecodeError):
                pass
    else:
        lines = [f"error: {_capped(error.message)}"]
    if error.fix:
        lines.append(f"  tip: {_capped(error.fix)}")
    return "\n".join(lines) + "\n"


#: Longest message and source line shown (a 140 KB expression must not print 140 KB).
_MAX_SHOWN = 2000
_MAX_SOURCE = 160


def _capped(text: str) -> str:
    return text if len(text) <= _MAX_SHOWN else f"{text[:_MAX_SHOWN // 2]} … {text[-_MAX_SHOWN // 4:]}"


def _window(source: str, column: int | None) -> tuple[str, int | None]:
    """The part of a long source line around ``column``, and the column in that part."""
    if len(source) <= _MAX_SOURCE:
        return source, column
    half = _MAX_SOURCE // 2
    start = 0 if column is None else max(0, min(column - 1 - half, len(source) - _MAX_SOURCE))
    part = source[start:start + _MAX_SOURCE]
    prefix = "… " if start > 0 else ""
    suffix = " …" if start + _MAX_SOURCE < len(source) else ""
    return prefix + part + suffix, None if column is None else column - start + len(prefix)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default: ``sys.argv[1:]``); return the exit code."""
    args = None
    try:
        argv = sys.argv[1:] if argv is None else list(argv)
        parser = _parser(argv[0] if argv and argv[0] in COMMANDS else None)
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        output = getattr(args, "output", None)
        if output:  # a read-only or missing folder is said before the work, not after it
            check_output(output)
        result = args.run(args)  # imports the command's work (SymPy, SciPy, ...): Ctrl-C there is handled below too
        if result is not None and output:
            write_output(output, result)
        elif result is not None:
            _to_stdout(result)
    except LagrangianError as exc:
        sys.stderr.write(format_error(exc))
        return exc.exit_code
    except KeyboardInterrupt as exc:
        # Ctrl-C: one line, no traceback, and the shell's convention for SIGINT (128 + 2).
        where = f" at t = {exc.t:.9g}" if isinstance(exc, Interrupted) else ""
        written = getattr(exc, "written", None)
        if isinstance(exc, EnsembleInterrupted):
            where = f" after {exc.done} of {exc.count} members"
            kept = f"; {written} keeps them (finish with --resume)" if written else "; nothing written"
        else:
            kept = f"; wrote the part computed so far to {written} (marked partial)" if written else \
                ("; nothing written" if getattr(args, "out", None) or getattr(args, "output", None) else "")
        sys.stderr.write(f"lagrangian: interrupted{where}{kept}\n")
        return 130
    except _ClosedOutput:  # `lagrangian derive | head`: the reader has gone, nothing more to say
        return 141  # 128 + SIGPIPE, as the shell reports a command killed by it
    return 0


class _ClosedOutput(Exception):
    """Standard output's reader closed the pipe."""


def _to_stdout(result: str | bytes) -> None:
    """Write ``result`` to standard output and flush it; a full device is an `OutputError`, not a traceback.

    After a failed write the rest of the buffer goes to the null device, so that Python's own flush
    at exit does not print a second error.
    """
    try:
        if isinstance(result, bytes):
            sys.stdout.flush()
            sys.stdout.buffer.write(result)
        else:
            sys.stdout.write(result)
        sys.stdout.flush()
    except BrokenPipeError:
        _drop_stdout()
        raise _ClosedOutput() from None
    except OSError as exc:
        _drop_stdout()
        raise OutputError(f"Cannot write to standard output: {exc.strerror or exc}.",
                          fix="free space where standard output goes, or write to a file with -o FILE") from None


def _drop_stdout() -> None:
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError, AttributeError):  # no file descriptor (a test's StringIO): nothing to drop
        pass


def entrypoint() -> None:
    """Console-script entry point."""
    code: int | str | None
    try:
        code = main()
    except SystemExit as exc:  # argparse's --help, --version and usage errors
        code = exc.code
    try:
        sys.stdout.flush()  # what argparse printed (--help): a full device is one line, not a traceback
    except BrokenPipeError:
        _drop_stdout()
    except OSError as exc:
        _drop_stdout()
        sys.stderr.write(f"error: cannot write to standard output: {exc.strerror or exc}\n")
        code = code or OutputError.exit_code
    if code == 130:
        # Ctrl-C: what was computed is written and closed, and the message is out.  The
        # interpreter's teardown of the loaded modules (xarray, zarr, SciPy) would still keep
        # the user waiting most of a second (several on a loaded machine), so the exit
        # handlers run and the process ends without it.
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)
        if run_exit_handlers is not None:
            run_exit_handlers()
        os._exit(130)
    raise SystemExit(code)


if __name__ == "__main__":  # python -m lagrangian.cli.main
    entrypoint()
