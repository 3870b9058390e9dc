"""Long generated C functions cut into parts, compiled as separate translation units in parallel.

A generated function is straight-line code, one statement per line (`_cprint`).  GCC's register
allocation grows much faster than linearly with the length of such a function: the 30-joint
arm's ``lg_aba_backward`` (6,565 statements) took 9.4 s of CPU as one function and 3.1 s in all
cut into parts of 700 statements, none over 0.7 s; the whole library, 16-19 s in one compiler
process, takes about 6.5 s of CPU in 35 units that run in parallel (`numerics._compile`).

A body longer than `MAX_STATEMENTS` becomes consecutive parts, each a C function of the same
arguments plus ``lg_w``, an array on the caller's stack: a local that a later part reads is
stored in its slot of ``lg_w`` where it is defined and read from there where it is used.  The
arithmetic is the same, statement for statement, in the same order (q̈ is equal to the last bit):
only where values live between statements changes, in ``lg_w`` rather than in the spill slots the
register allocator of one long function chose.

The parts are written twice: in the one translation unit `source` (``static``, not inlined, so
that a compiler given the whole sees the same functions), and each in a unit of its own for the
parallel build (`units_of`: external, but hidden from the library's exported symbols).

The parts of a function that runs once per output sample or per parameter set, not at each step
(the monitors, the hoisted constants), are *cold*: their units open with `COLD_UNIT`, and the
build compiles them for the compiler's speed rather than the code's (`numerics._compile`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

__all__ = ["COLD_UNIT", "MAX_STATEMENTS", "PART_MACROS", "Part", "function_text", "part_unit", "units_of"]

#: Most statements of one part (and of a function left whole).
MAX_STATEMENTS = 700

#: The first line of a cold part's unit: code that runs once per output sample or per parameter set.
COLD_UNIT = "/* lagrangian: cold (runs once per output sample or per parameter set) */\n"

#: What the parts' declarations mean, in the one-unit source and in the units of a parallel build.
PART_MACROS = {
    "source": "#if defined(__GNUC__)\n#define LG_PART static __attribute__((noinline))\n#else\n"
              "#define LG_PART static\n#endif",
    "unit": "#if defined(__GNUC__)\n#define LG_PART __attribute__((visibility(\"hidden\")))\n#else\n"
            "#define LG_PART\n#endif",
}

_DEFINITION = re.compile(r"^\s*const double (\w+) = ")
_IDENTIFIER = re.compile(r"\b[A-Za-z_]\w*\b")
#: Names read from the arguments (``_y3`` is y[3], ``_p1`` p[1], ``_t`` t, ``_k0`` a hoisted constant).
_ARGUMENT_NAME = re.compile(r"\b_[ypkt]\w*")


@dataclass(frozen=True)
class Part:
    """One part of a long function: its declaration (``LG_PART void name(...)``), its C text, and whether
    it is cold (run once per output sample or per parameter set, not at each step)."""

    declaration: str
    text: str
    cold: bool = False


def _declarations(header: Mapping[str, str], lines: Sequence[str]) -> list[str]:
    used = set(_ARGUMENT_NAME.findall("\n".join(lines)))
    return [f"    const double {c} = {v};" for c, v in header.items() if c in used]


def _argument_names(arguments: str) -> list[str]:
    """``"double t, const double *y"`` → ``["t", "y"]``."""
    return [a.replace("*", " ").split()[-1] for a in arguments.split(",") if a.strip()]


def function_text(signature: str, header: Mapping[str, str], body: Sequence[str], parts: list[Part],
                  preamble: Sequence[str] = (), *, limit: int | None = None, cold: bool = False) -> str:
    """``signature { declarations; body }``, in parts (appended to ``parts``) when the body is long.

    ``header`` maps the names the body may read from the arguments to their C expressions
    (``_y3`` → ``y[3]``): a whole function declares those it uses first, as locals; a part reads
    each where it uses it (``y[3]``), like the locals of earlier parts (``lg_w[12]``), so that no
    copy of them is held for the whole part (a part's register allocator would spill most of them
    to its stack: measured on the 30-joint arm, q̈ 7 % faster so than with the copies).
    ``preamble`` lines open the function (``lg_constants`` defines t and y there).  ``limit``:
    the most statements of a part, default `MAX_STATEMENTS`.  ``cold``: the function runs once per
    output sample or per parameter set (its parts are compiled for speed of compiling).

    The outputs (``M[3] = ...``) stay where the generators put them, after the locals: moved up
    between the statements, they are stores that the compiler must assume may change ``y`` and
    ``p``, and q̈ was 20 % slower.
    """
    limit = MAX_STATEMENTS if limit is None else limit
    name_match = re.search(r"(\w+)\(([^)]*)\)\s*$", signature)
    if len(body) <= limit or name_match is None:
        lines = [*preamble, *_declarations(header, body), "    (void)t; (void)y; (void)p;", *body]
        return signature + " {\n" + "\n".join(lines) + "\n}\n"
    name, arguments = name_match.groups()
    names = _argument_names(arguments)
    chunks = [list(body[k:k + limit]) for k in range(0, len(body), limit)]
    defined_in: dict[str, int] = {}
    for c, chunk in enumerate(chunks):
        for line in chunk:
            m = _DEFINITION.match(line)
            if m:
                defined_in[m.group(1)] = c
    slots: dict[str, int] = {}
    for c, chunk in enumerate(chunks):
        used = {word for line in chunk for word in _IDENTIFIER.findall(line.partition("=")[2])}
        for w in sorted((w for w in used if defined_in.get(w, c) < c), key=lambda w: (defined_in[w], w)):
            slots.setdefault(w, len(slots))
    calls = []
    for c, chunk in enumerate(chunks):
        part = f"{name}_part{c}"
        declaration = f"LG_PART void {part}({arguments}, double *restrict lg_w)"
        lines = [*preamble, "    " + " ".join(f"(void){a};" for a in [*names, "lg_w"])]
        # What this part writes for a name: an earlier part's local from its slot, an argument's value in place.
        reads = {**header, **{w: f"lg_w[{k}]" for w, k in slots.items() if defined_in[w] < c}}
        for line in chunk:
            target, _, value = line.partition("=")
            lines.append(target + "=" + _IDENTIFIER.sub(lambda w, r=reads: r.get(w[0], w[0]), value))
            m = _DEFINITION.match(line)
            if m and m.group(1) in slots:  # a later part reads it: stored once, as soon as it is defined
                lines.append(f"    lg_w[{slots[m.group(1)]}] = {m.group(1)};")
        parts.append(Part(declaration, declaration + " {\n" + "\n".join(lines) + "\n}\n", cold))
        calls.append(f"    {part}({', '.join([*names, 'lg_w'])});")
    # The values carried between parts, on the caller's stack (as the spill slots of one long function were).
    return signature + " {\n" + f"    double lg_w[{max(len(slots), 1)}];\n" + "\n".join(calls) + "\n}\n"


def part_unit(part: Part) -> str:
    """The translation unit of one part in a parallel build: the part alone, with what it needs of C."""
    return (COLD_UNIT if part.cold else "") + "#include <math.h>\n" + PART_MACROS["unit"] + "\n" + part.text


def units_of(parts: Sequence[Part], main: str) -> tuple[str, ...]:
    """The translation units of a parallel build: ``main`` (which declares the parts), then one per part."""
    return (main, *(part_unit(part) for part in parts))
