#!/usr/bin/env python3
"""Fuzz campaign: mutated model files through every stage of `lagrangian`.

Each case is an example model file (``examples/*.toml``) with one to three mutations:

- *token* mutations inside an expression string: a number replaced by an extreme one
  (``1e400``, ``-0``, ``1e-320``, ``nan``), a name by another name, a function or an
  unknown frame, a token deleted, duplicated or an operator inserted, the expression
  wrapped in ``sqrt``/``log``/``exp``/… or raised to a power;
- *structural* mutations of the TOML: lines and tables deleted, duplicated, swapped or
  renamed, a value of another type, the file cut short, odd characters inserted, deep
  nesting;
- with ``--format urdf``, the robots of ``examples/*.urdf`` instead: attribute values replaced (extreme
  numbers, axes of zero length, names of other links, payloads), joint types swapped, lines deleted,
  duplicated or cut, and XML attacks (entity expansion, external entities, deep nesting), a parent
  made its own child (a cycle), elements URDF readers skip (transmissions, mimic of nothing);
- the known *bombs* (``((theta+2)^1000)^1000``, ``1e400``, ``sqrt(-1)``,
  ``exp(exp(exp(1000)))``, ``a = [[[…]]]`` 500 deep, …) and *payloads* that would create
  a canary file if any text were ever evaluated or handed to a shell.

Every case runs in its own forked process (the parent imports `lagrangian` once) under a
memory cap (``RLIMIT_AS``, 4 GiB by default) and a time cap, through the stages
``load → derive → integrals → verify → compile → simulate → report`` and then one command
of the command line (``derive``, ``derive --latex``, ``simulate``, ``verify``, ``report``,
``analyse``, ``equilibria``, ``linearize``, ``modes``, ``export``), its output to a file.  Each case ends in one outcome:

``ok``         every stage ran;
``error``      a stage refused the input with a `lagrangian` error (the expected way out);
``traceback``  an exception that is not a `lagrangian` error escaped (a bug);
``hang``       the time cap was reached (the process was killed);
``memory``     `MemoryError`, or the process died allocating (the memory cap was reached);
``signal``     the process died of a signal (SIGSEGV, SIGBUS, SIGABRT, ...);
``code``       the canary file exists: some text was executed.

The summary (``summary.json`` and a table on standard output) counts the outcomes; every
case that is not ``ok`` or ``error`` is kept under ``OUT/findings/`` (the model file and
what happened) so it can be replayed with ``--replay FILE``.

Short run (part of the test suite, tests/fuzz/test_fuzz.py)::

    python tools/fuzz.py --cases 30 --seed 1

Long run (docs/fuzzing.md)::

    nice python tools/fuzz.py --cases 100000 --seed 2 --jobs 2 --out fuzz-out
"""

from __future__ import annotations

import argparse
import contextlib
import faulthandler
import gc
import hashlib
import io
import json
import os
import random
import re
import resource
import select
import shutil
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

OUTCOMES = ("ok", "error", "traceback", "hang", "memory", "signal", "code")
#: The outcomes that are defects.
BAD = ("traceback", "hang", "memory", "signal", "code")

# -- mutations --------------------------------------------------------------------------------------

#: Numbers that have broken parsers and integrators before.
NUMBERS = ("0", "-0", "0.0", "1e400", "-1e400", "1e308", "1.8e308", "1e-320", "5e-324", "1e-400", "nan", "inf",
           "99999999999999999999999", "1_0", "0x10", "1e", ".", "1..2", "2^1024", "10^400", "-1", "1000000",
           "1e16", "٣", "²")
#: Names to put where a name was: functions, coordinates' rates, time, frames and vectors that exist or not.
NAMES = ("sin", "cos", "tan", "sqrt", "log", "exp", "asin", "acos", "atan", "atan2", "sinh", "abs", "sign", "t",
         "pi", "E", "I", "oo", "nan", "zoo", "R0", "R0.x", "R0.w", "R9.x", "R1.z", "R0.x.y", "__import__", "os",
         "lambda", "x_dot", "theta_dot", "theta_ddot", "ψ", "θ", "inf", "True", "None", "self", "__class__")
OPERATORS = ("+", "-", "*", "/", "^", "**", "(", ")", ",", ".", "'", "!", "%", "==", "<", "&", "|", "@", "\\", "#")
WRAPPERS = ("sqrt({})", "log({})", "exp({})", "exp(exp({}))", "asin({})", "acos({})", "tan({})", "1/({})",
            "({})/0", "({})^1000", "({})^33", "({})^-1", "({})^0.5", "({}-({}))", "1/({}-({}))", "({})*1e308",
            "({})+1e309", "({})^(1/3)", "abs({})", "sign({})", "atan2({}, 0)", "({})!", "-({})", "(({})))",
            "sin(sin(sin(sin(sin(sin(sin(sin({}))))))))", "({})^({})")
#: The reproducers found so far and their relatives (expressions).
BOMBS = ("((theta+2)^1000)^1000", "(theta+1)^1000", "(1+theta^2)^1000", "x^99999", "1e400", "1e1000", "sqrt(-1)",
         "log(-1)", "exp(exp(exp(1000)))", "theta+log(psi)", "theta+1e309", "-m", "m*(1+t)", "0", "m*theta",
         "((((((((((theta))))))))))" * 1, "(" * 300 + "1" + ")" * 300, "theta" + "+theta" * 3000,
         "+".join(f"theta^{k}" for k in range(40)), "theta*" * 200 + "1", "sin(" * 200 + "0" + ")" * 200,
         "x^2+y^2-l^2+1e400*x", "1/0", "0/0", "0^0", "0^-1", "(-1)^(1/2)", "acos(2)", "atan2(0, 0)",
         "(a+b+c+d)^20", "((theta^4)^4)^4", "2^2^2^2^2^2", "10^10^10", "1" + "0" * 400, "9" * 5000, "theta" * 3000,
         "x" * 25000, "1e-400", "-0", "\u202etheta", "theta\x00", "θ", "R0.x", "R0.x*R0.y", "1/(theta-theta)")
#: Texts that would leave the canary file behind if anything evaluated them (``{canary}`` is its path).
PAYLOADS = ("__import__('os').system('touch {canary}')", "$(touch {canary})", "`touch {canary}`",
            "; touch {canary}", "{{{{7*7}}}}", "exec(\"open('{canary}','w')\")", "eval('1')",
            "lambda: open('{canary}', 'w')", "().__class__.__base__.__subclasses__()", "os.system('touch {canary}')",
            "getattr(__builtins__, 'open')('{canary}', 'w')", "#!/bin/sh\ntouch {canary}")
#: Whole TOML fragments: structures that broke the reader before.
FRAGMENTS = ("a = " + "[" * 500 + "]" * 500, "a = " + "{b = " * 300 + "1" + "}" * 300, "[bodies.S.inertia]\nA = 1",
             "[bodies.S]\nmass = \"m\"", "[[frames]]", "[frames.R9]\nfrom = \"R9\"", "[frames]\nR5 = { from = \"R5\" }",
             "[coordinates]\nq = { initial = 1e400 }", "x = \"\"\"", "key = 'unterminated", "[", "= 1", "\ufeff",
             "[loads]\nspring = { potential = \"1e400*theta\" }", "[parameters]\nm = -1",
             "[parameters]\nm = 1e400", "[parameters]\nm = nan", "[parameters]\nm = \"sqrt(-1)\"",
             "[coordinates]\ntheta = { initial = \"x\", rate = [] }", "[model]\nname = \"<iframe src=x>\"",
             "[model]\nname = \"\\\\frac{a}{b}\"", "[particles.Q]\nmass = \"m\"\nposition = \"R7.x\"")
ODD = ("\x00", "\x1b[2J", "\u202e", "\ufeff", "²", "٣", "é", "\ud7ff", "\t", "\r", "\\", "\"", "'", "#", "=", "[", "]",
       "{", "}", "\n", "  ", "\u00a0", "𝜃")

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z_0-9.]*|\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+|\s+|.", re.S)
_STRING = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
_HEADER = re.compile(r"^\s*\[")


def _strings(text: str) -> list[re.Match]:
    return [m for m in _STRING.finditer(text)]


def _mutate_expression(rng: random.Random, expr: str, canary: str, names: list[str]) -> str:
    tokens = _TOKEN.findall(expr) or [""]
    kind = rng.randrange(10)
    i = rng.randrange(len(tokens))
    if kind == 0:  # a number replaced
        spots = [k for k, t in enumerate(tokens) if t[:1].isdigit() or t[:1] == "."] or [i]
        tokens[rng.choice(spots)] = rng.choice(NUMBERS)
    elif kind == 1:  # a name replaced
        spots = [k for k, t in enumerate(tokens) if t[:1].isalpha() or t[:1] == "_"] or [i]
        tokens[rng.choice(spots)] = rng.choice(NAMES + tuple(names))
    elif kind == 2:
        del tokens[i]
    elif kind == 3:
        tokens.insert(i, tokens[i])
    elif kind == 4:
        tokens.insert(i, rng.choice(OPERATORS))
    elif kind == 5:
        return rng.choice(WRAPPERS).replace("{}", expr)
    elif kind == 6:
        return rng.choice(BOMBS)
    elif kind == 7:
        return rng.choice(PAYLOADS).format(canary=canary)
    elif kind == 8:  # a sub-expression repeated: sizes grow
        return "(" + expr + ")" + rng.choice("+*^") + "(" + expr + ")"
    else:
        tokens.insert(i, rng.choice(ODD))
    return "".join(tokens)


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\x00", "\\u0000")


def _mutate_token(rng: random.Random, text: str, canary: str) -> str:
    strings = _strings(text)
    if not strings:
        return text
    names = sorted(set(re.findall(r"[A-Za-z_][A-Za-z_0-9]*", text)))[:200]
    m = rng.choice(strings)
    new = _mutate_expression(rng, m.group(1), canary, names)
    return text[:m.start()] + '"' + _escape(new) + '"' + text[m.end():]


def _tables(lines: list[str]) -> list[tuple[int, int]]:
    heads = [k for k, line in enumerate(lines) if _HEADER.match(line)]
    return [(a, b) for a, b in zip(heads, heads[1:] + [len(lines)], strict=True)]


def _mutate_structure(rng: random.Random, text: str, canary: str) -> str:
    lines = text.split("\n")
    kind = rng.randrange(12)
    i = rng.randrange(len(lines))
    j = rng.randrange(len(lines))
    tables = _tables(lines)
    if kind == 0:
        del lines[i]
    elif kind == 1:
        lines.insert(j, lines[i])
    elif kind == 2:
        lines[i], lines[j] = lines[j], lines[i]
    elif kind == 3 and tables:  # a table deleted
        a, b = rng.choice(tables)
        del lines[a:b]
    elif kind == 4 and tables:  # a table duplicated or moved
        a, b = rng.choice(tables)
        block = lines[a:b]
        if rng.random() < 0.5:
            del lines[a:b]
        at = rng.randrange(len(lines) + 1)
        lines[at:at] = block
    elif kind == 5 and tables:  # a table renamed: a sub-table without its parent, an unknown kind, ...
        a, _ = rng.choice(tables)
        name = lines[a].strip().strip("[]")
        lines[a] = "[" + rng.choice((name + ".inertia", name + ".x", "bodies.S.inertia", "particles", name.upper(),
                                     name + "." + name, "frames.R0", "loads.extra", "")) + "]"
    elif kind == 6:  # a value of another type
        k = rng.randrange(len(lines))
        if "=" in lines[k]:
            key = lines[k].split("=", 1)[0]
            value = rng.choice(("1e400", "-1", "0", "[]", "{}", "true", '"nan"', '""', "[1, 2, 3]", '"R0"',
                                "{ value = 1e400 }", "{ initial = nan }", "2024-01-01", '"1e400"', '"sqrt(-1)"',
                                "{ from = \"R0\", rotation = [\"theta\"] }", "-inf", "9" * 30))
            lines[k] = key + "= " + value
    elif kind == 7:  # cut short
        cut = rng.randrange(len(text) + 1)
        return text[:cut]
    elif kind == 8:  # an odd character somewhere
        at = rng.randrange(len(text) + 1)
        return text[:at] + rng.choice(ODD) + text[at:]
    elif kind == 9:  # a known fragment appended or inserted
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(FRAGMENTS))
    elif kind == 10:  # a key renamed
        k = rng.randrange(len(lines))
        if "=" in lines[k]:
            key, value = lines[k].split("=", 1)
            lines[k] = rng.choice(("mass", "position", "rotation", "from", "inertia", "initial", "rate", "value",
                                   "potential", "gravity", "holonomic", "axes", "__class__", "R0", "theta")) + " =" + value
    else:  # a whole value replaced by a payload
        strings = _strings(text)
        if strings:
            m = rng.choice(strings)
            return text[:m.start()] + '"' + _escape(rng.choice(PAYLOADS).format(canary=canary)) + '"' + text[m.end():]
    return "\n".join(lines)


#: XML fragments that broke XML readers (or would read a file, or the canary, if entities were expanded).
URDF_FRAGMENTS = (
    '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
    '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">]>',
    '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>', '<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{canary}">]>',
    '<!DOCTYPE robot [<!ENTITY % p SYSTEM "http://127.0.0.1:9/x.dtd"> %p;]>', "<a>" * 3000 + "</a>" * 3000,
    '<joint name="free" type="floating"><parent link="base"/><child link="extra"/></joint><link name="extra"/>',
    '<joint name="flat" type="planar"><parent link="base"/><child link="extra"/></joint><link name="extra"/>',
    '<joint name="copy" type="revolute"><parent link="base"/><child link="twin"/><axis xyz="0 0 1"/>'
    '<mimic joint="nowhere" multiplier="2"/></joint><link name="twin"/>',
    '<transmission name="t"><type>SimpleTransmission</type></transmission>', '<gazebo reference="base"/>',
    "<?xml-stylesheet href='x'?>", "<![CDATA[ <robot> ]]>", "&x;", "<robot name='second'/>", "<link/>", "<joint/>",
    '<link name="heavy"><inertial><mass value="1e308"/><inertia ixx="1e308" ixy="0" ixz="0" iyy="1e308" iyz="0" '
    'izz="1e308"/></inertial></link>',
)
URDF_VALUES = ("0 0 0", "0 0 1e400", "nan 0 1", "1 2", "1 2 3 4", "0,0,1", "", " ", "-1", "0", "1e-320", "1e308",
               "inf", "x", "base", "world", "revolute", "floating", "planar", "continuous", "prismatic", "fixed", "bogus",
               "&amp;", "${pi/2}", "$(arg x)", "1_0", "٣", "x" * 5000)


def _mutate_urdf(rng: random.Random, text: str, canary: str) -> tuple[str, str]:
    """One mutation of a URDF file: (text, what)."""
    attributes = list(re.finditer(r'(\w+)="([^"]*)"', text))
    names = sorted(set(re.findall(r'name="([^"]*)"', text))) or ["base"]
    kind = rng.randrange(10)
    if kind < 5 and attributes:  # an attribute's value replaced
        m = rng.choice(attributes)
        old = m.group(2).split()
        choice = rng.randrange(6)
        if choice == 0 and len(old) == 3:  # one component of a vector
            old[rng.randrange(3)] = rng.choice(NUMBERS)
            new = " ".join(old)
        elif choice == 1:
            new = rng.choice(names)  # a link of another joint: cycles, a child with two parents, itself
        elif choice == 2:
            new = rng.choice(PAYLOADS).format(canary=canary).replace('"', "&quot;").replace("<", "&lt;")
        elif choice == 3:
            new = rng.choice(NUMBERS)
        else:
            new = rng.choice(URDF_VALUES)
        return text[:m.start(2)] + new + text[m.end(2):], "attribute"
    lines = text.split("\n")
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    if kind == 5:
        del lines[i]
    elif kind == 6:
        lines.insert(j, lines[i])
    elif kind == 7:  # a fragment, after the XML declaration when it is a DOCTYPE
        fragment = rng.choice(URDF_FRAGMENTS).format(canary=canary)
        at = 1 if fragment.startswith("<!DOCTYPE") else rng.randrange(1, len(lines) + 1)
        lines.insert(at, fragment)
        if fragment.startswith("<!DOCTYPE") and "ENTITY" in fragment:
            entity = re.search(r"ENTITY (?:% )?(\w+)", fragment).group(1)  # type: ignore[union-attr]
            k = rng.randrange(2, len(lines))
            lines[k] = lines[k].replace('name="', f'name="&{entity};', 1) if 'name="' in lines[k] else \
                lines[k] + f"&{entity};"
    elif kind == 8:
        return text[:rng.randrange(len(text) + 1)], "structure"
    else:
        at = rng.randrange(len(text) + 1)
        return text[:at] + rng.choice(ODD) + text[at:], "structure"
    return "\n".join(lines), "structure"


def make_case(rng: random.Random, sources: dict[str, str], canary: str) -> tuple[str, str, list[str]]:
    """A mutated model: (the example's name, the text, the mutations applied)."""
    name = rng.choice(sorted(sources))
    text = sources[name]
    done = []
    for _ in range(rng.choice((1, 1, 1, 2, 2, 3))):
        if name.endswith(".urdf"):
            text, what = _mutate_urdf(rng, text, canary)
        elif rng.random() < 0.6:
            text, what = _mutate_token(rng, text, canary), "token"
        else:
            text, what = _mutate_structure(rng, text, canary), "structure"
        done.append(what)
    return name, text, done


def draw(rng: random.Random, sources: dict[str, str], canary: str, seen: set[bytes]) -> tuple[str, str, list[str], int]:
    """The campaign's next new case: (example, text, mutations, redraws).

    A text already run would run the same way again (the stages are deterministic): drawn again
    instead, so that every case is a new input (1 draw in ~10 repeats an earlier one).
    """
    redraws = 0
    for _ in range(100):
        name, text, mutations = make_case(rng, sources, canary)
        digest = hashlib.blake2b(text.encode("utf-8", "surrogateescape"), digest_size=16).digest()
        if digest not in seen:
            break
        redraws += 1
    seen.add(digest)
    return name, text, mutations, redraws


def _sources(model_format: str, examples: list[str] | None, exclude: list[str]) -> dict[str, str]:
    chosen = sorted(EXAMPLES.glob(f"*.{model_format}"))
    if examples:
        chosen = [p for p in chosen if p.stem in examples]
    chosen = [p for p in chosen if p.stem not in exclude]
    # URDF sources keep their suffix in the name: the case file must end in .urdf to be read as one.
    return {(p.name if model_format == "urdf" else p.stem): p.read_text(encoding="utf-8") for p in chosen}


def show_case(seed: int, number: int, out: Path, *, examples: list[str] | None = None, exclude: list[str] = (),
              model_format: str = "toml") -> tuple[str, dict]:
    """Case ``number`` of the campaign of ``seed`` written to ``out`` (same examples): its text and what it
    is, without running any; for a case that was not kept (a slow one under the threshold, an error
    worth reading).

    A payload's canary path is part of the text, and its length moves the positions drawn by the
    mutations after it: the cases are drawn again with canary paths as long as the campaign's
    (``OUT/cases-XXXXXXXX/NNNNNN/CANARY``, the eight characters of `tempfile.mkdtemp`), so the same
    ``--out`` gives the same cases, but for the eight characters in the payloads.
    """
    sources = _sources(model_format, examples, list(exclude))
    rng = random.Random(seed)
    seen: set[bytes] = set()
    work = Path(out).resolve() / "cases-xxxxxxxx"
    for k in range(number + 1):
        name, text, mutations, _ = draw(rng, sources, str(work / f"{k:06d}" / "CANARY"), seen)
        command = COMMANDS[rng.randrange(len(COMMANDS))]
    return text, {"example": name, "mutations": mutations, "command": command, "case": number}


# -- one case, in a forked child ---------------------------------------------------------------------

#: The command-line runs of the last stage (MODEL and OUT are replaced).
COMMANDS = (["derive", "MODEL"], ["derive", "--latex", "MODEL", "-o", "OUT/d.tex"],
            ["derive", "--json", "MODEL", "-o", "OUT/d.json"],
            ["simulate", "MODEL", "--t-end", "0.3", "--n-out", "7", "-o", "OUT/t.csv"],
            ["simulate", "MODEL", "--t-end", "0.3", "--n-out", "7", "--method", "gauss-legendre"],
            ["verify", "MODEL"], ["report", "MODEL", "--lang", "en", "-o", "OUT/r.md"],
            ["analyse", "MODEL"], ["simulate", "MODEL", "--t-end", "0.3", "--event", "R0.x"],
            ["equilibria", "MODEL"], ["linearize", "MODEL"], ["modes", "MODEL"],
            ["export", "MODEL", "--to", "numpy", "-o", "OUT/export"], ["export", "MODEL", "--to", "c", "-o", "OUT/c"])


def _stages(path: str, out: str, command: list[str]):
    """The stages, each a (name, callable) run in turn while the previous ones succeeded."""
    import lagrangian
    from lagrangian.cli.main import main

    state: dict = {}

    def cli():
        argv = [a.replace("MODEL", path).replace("OUT", out) for a in command]
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse's usage errors
                code = exc.code
        if "Traceback" in stderr.getvalue():
            raise RuntimeError("the command printed a traceback:\n" + stderr.getvalue()[-3000:])
        return {"argv": command, "exit": code, "stderr": stderr.getvalue()[:500],
                "stderr_chars": len(stderr.getvalue())}

    return [
        ("load", lambda: state.__setitem__("model", lagrangian.load_model(path))),
        ("derive", lambda: state.__setitem__("eom", lagrangian.derive(state["model"]))),
        ("integrals", lambda: state.__setitem__("integrals", lagrangian.first_integrals(state["eom"]))),
        ("verify", lambda: lagrangian.verify(state["eom"])),
        ("compile", lambda: state.__setitem__("system", lagrangian.compile_system(state["eom"]))),
        # the system the stage before compiled: generating the same C again would only repeat that stage
        ("simulate", lambda: lagrangian.simulate(state["system"], 0.3, n_out=7)),
        # with the stage's integrals, not a second search for them (the command line's report searches)
        ("report", lambda: lagrangian.report(state["eom"], lang="en", integrals=state["integrals"]).markdown()),
    ], cli


def run_case(path: str, out: str, command: list[str], result_file: str) -> None:
    """Run every stage on the model file at ``path``; write what happened to ``result_file`` (JSON)."""
    from lagrangian.errors import LagrangianError

    stages, cli = _stages(path, out, command)
    record: dict = {"stages": [], "outcome": "ok"}
    for name, stage in stages + [("cli", cli)]:
        start = time.perf_counter()
        entry: dict = {"stage": name}
        record["running"] = name  # a hang or a crash is then put on this stage
        _write_json(result_file, record)
        try:
            value = stage()
            if name == "cli":
                entry["cli"] = value
            entry["outcome"] = "ok"
        except LagrangianError as exc:
            entry.update(outcome="error", message=str(exc)[:300], message_chars=len(str(exc)))
        except MemoryError:
            entry.update(outcome="memory", message=traceback.format_exc()[-2000:])
        except BaseException as exc:  # noqa: BLE001 -- that is what we are looking for
            entry.update(outcome="traceback", type=type(exc).__name__, message=traceback.format_exc()[-4000:])
        entry["seconds"] = round(time.perf_counter() - start, 3)
        record["stages"].append(entry)
        _write_json(result_file, record)  # so that a later death still shows where it got to
        if entry["outcome"] != "ok":
            if entry["outcome"] != "error" or name == "cli":
                record["outcome"] = entry["outcome"]
            else:
                record["outcome"] = "error"
            if name != "cli":
                record["running"] = "cli"
                _write_json(result_file, record)
                record["stages"].append(_cli_after(cli))
                if record["stages"][-1]["outcome"] in BAD:
                    record["outcome"] = record["stages"][-1]["outcome"]
            break
    record.pop("running", None)
    _write_json(result_file, record)


def _cli_after(cli) -> dict:
    """The command line is run on every case, even one a stage refused (it must refuse it cleanly)."""
    from lagrangian.errors import LagrangianError

    start = time.perf_counter()
    entry: dict = {"stage": "cli"}
    try:
        entry.update(outcome="ok", cli=cli())
    except LagrangianError as exc:  # main() catches these; one that escapes is a defect of the boundary
        entry.update(outcome="traceback", type=type(exc).__name__, message=str(exc)[:500])
    except MemoryError:
        entry.update(outcome="memory", message=traceback.format_exc()[-2000:])
    except BaseException as exc:  # noqa: BLE001
        entry.update(outcome="traceback", type=type(exc).__name__, message=traceback.format_exc()[-4000:])
    entry["seconds"] = round(time.perf_counter() - start, 3)
    return entry


def _write_json(path: str, record: dict) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(record, f)
    os.replace(tmp, path)


def _child(case_dir: Path, model_file: Path, command: list[str], memory: int) -> None:
    """In the forked child: cap the memory, send the output to files, run the case, never return."""
    code = 0
    try:
        _die_with_parent()
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        for fd, name in ((1, "stdout.txt"), (2, "stderr.txt")):
            handle = os.open(case_dir / name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            os.dup2(handle, fd)
            os.close(handle)
        faulthandler.enable()  # a crash's Python stack goes to the case's stderr.txt (not the campaign's)
        os.chdir(case_dir)
        run_case(str(model_file), str(case_dir), command, str(case_dir / "result.json"))
    except MemoryError:
        code = 71
    except BaseException:  # noqa: BLE001
        with contextlib.suppress(Exception):
            os.write(2, traceback.format_exc().encode("utf-8", "replace"))
        code = 70
    finally:
        with contextlib.suppress(Exception):
            sys.stdout.flush()
            sys.stderr.flush()
        os._exit(code)


def _die_with_parent() -> None:
    """Linux: the case is killed when the campaign is (no orphan left running with its 4 GiB)."""
    with contextlib.suppress(Exception):
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


class Running:
    """A forked case: its process, start time and files."""

    def __init__(self, number: int, pid: int, case_dir: Path, meta: dict) -> None:
        self.number, self.pid, self.case_dir, self.meta = number, pid, case_dir, meta
        self.start = time.monotonic()
        self.killed = False


def _classify(run: Running, status: int, canary: Path) -> dict:
    result_file = run.case_dir / "result.json"
    record = json.loads(result_file.read_text(encoding="utf-8")) if result_file.exists() else {"stages": []}
    stderr = (run.case_dir / "stderr.txt").read_text(encoding="utf-8", errors="replace") \
        if (run.case_dir / "stderr.txt").exists() else ""
    if run.killed:
        record["outcome"] = "hang"
    elif os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        memory = any(s in stderr for s in ("bad_alloc", "MemoryError", "Cannot allocate", "out of memory"))
        record["outcome"] = "memory" if memory else "signal"
        record["signal"] = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else sig
    elif os.WEXITSTATUS(status) != 0 and record.get("outcome") in (None, "ok", "error"):
        record["outcome"] = "memory" if os.WEXITSTATUS(status) == 71 or "MemoryError" in stderr else "traceback"
        record["exit"] = os.WEXITSTATUS(status)
    record.setdefault("outcome", "traceback")
    if canary.exists():
        record["outcome"] = "code"
    record["stderr_tail"] = stderr[-2000:]
    record["seconds"] = round(time.monotonic() - run.start, 2)
    record.update(run.meta)
    return record


def campaign(cases: int, seed: int, out: Path, *, jobs: int = 1, time_limit: float = 30.0,
             memory_gib: float = 4.0, examples: list[str] | None = None, exclude: list[str] = (),
             quiet: bool = False, replay: list[Path] | None = None, warm_up: bool = True,
             model_format: str = "toml", slow_s: float = 10.0) -> dict:
    """Run ``cases`` mutated models (or the files of ``replay``); return the summary (also in OUT/summary.json)."""
    import lagrangian  # noqa: F401 -- imported once here, shared by every forked case

    out = Path(out).resolve()  # each case chdirs into its own folder: a relative --out would be lost
    out.mkdir(parents=True, exist_ok=True)
    (out / "findings").mkdir(exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="cases-", dir=out))  # cases-XXXXXXXX: see _canary
    os.environ.setdefault("LAGRANGIAN_CACHE", str(out / "cache"))
    sources = _sources(model_format, examples, list(exclude))
    rng = random.Random(seed)
    memory = int(memory_gib * 2**30)
    if warm_up:
        _warm_up(work)
    # The objects imported so far go to the collector's permanent generation: a forked case's
    # collections then leave them alone instead of touching (and so copying) their pages.
    gc.freeze()
    counts: Counter = Counter()
    stage_counts: Counter = Counter()
    stage_seconds: Counter = Counter()
    findings: list[dict] = []
    slowest: list[tuple[float, int]] = []
    slow: list[dict] = []  # the cases over slow_s: not defects (a loaded machine slows them), kept to replay
    running: dict[int, Running] = {}
    seen: set[bytes] = set()  # digests of the model texts run so far
    duplicates = [0]
    started = time.monotonic()
    total = len(replay) if replay else cases

    def start(number: int) -> None:
        case_dir = work / f"{number:06d}"
        case_dir.mkdir()
        canary = case_dir / "CANARY"
        if replay:
            text, meta = replay[number].read_text(encoding="utf-8", errors="surrogateescape"), \
                {"example": replay[number].name, "mutations": ["replay"]}
        else:
            name, text, mutations, redraws = draw(rng, sources, str(canary), seen)
            duplicates[0] += redraws
            meta = {"example": name, "mutations": mutations}
        command = COMMANDS[(number if replay else rng.randrange(len(COMMANDS))) % len(COMMANDS)]
        if replay:  # a finding replays with the command it had (its record beside it), others take turns
            record = replay[number].with_suffix(".json")
            with contextlib.suppress(OSError, ValueError, KeyError, TypeError):
                command = [str(a) for a in json.loads(record.read_text(encoding="utf-8"))["command"]]
        meta.update(case=number, command=command)
        suffix = replay[number].suffix if replay else (".urdf" if meta["example"].endswith(".urdf") else ".toml")
        model_file = case_dir / f"model{suffix}"
        model_file.write_text(text, encoding="utf-8", errors="surrogateescape")
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            _child(case_dir, model_file, command, memory)
        running[pid] = Running(number, pid, case_dir, meta)

    def finish(run: Running, status: int) -> None:
        record = _classify(run, status, run.case_dir / "CANARY")
        outcome = record["outcome"]
        counts[outcome] += 1
        for entry in record.get("stages", []):
            stage_counts[(entry["stage"], entry["outcome"])] += 1
            stage_seconds[entry["stage"]] += entry.get("seconds", 0.0)
        slowest.append((record["seconds"], run.number))
        if outcome in BAD:
            name = f"{outcome}-{run.number:06d}"
            (model_file,) = [p for p in run.case_dir.iterdir() if p.stem == "model" and p.suffix in (".toml", ".urdf")]
            shutil.copyfile(model_file, out / "findings" / f"{name}{model_file.suffix}")
            (out / "findings" / f"{name}.json").write_text(json.dumps(record, indent=1), encoding="utf-8")
            findings.append({"case": run.number, "outcome": outcome, "file": f"findings/{name}{model_file.suffix}",
                             "stage": next((e["stage"] for e in record.get("stages", []) if e["outcome"] in BAD),
                                           record.get("running")),
                             "what": _what(record)})
            if not quiet:
                print(f"case {run.number}: {outcome} ({findings[-1]['stage']}): {findings[-1]['what']}", flush=True)
        elif record["seconds"] > slow_s:
            (model_file,) = [p for p in run.case_dir.iterdir() if p.stem == "model" and p.suffix in (".toml", ".urdf")]
            name = f"slow-{run.number:06d}{model_file.suffix}"
            shutil.copyfile(model_file, out / "findings" / name)
            slow.append({"case": run.number, "seconds": record["seconds"], "file": f"findings/{name}",
                         "stage": record["stages"][-1]["stage"] if record.get("stages") else None})
        shutil.rmtree(run.case_dir, ignore_errors=True)

    def summary() -> dict:
        done = sum(counts.values())
        record = {"cases": done, "planned": total, "seed": seed, "seconds": round(time.monotonic() - started, 1),
                  "duplicates_redrawn": duplicates[0],
                  "time_limit_s": time_limit, "memory_gib": memory_gib,
                  "outcomes": {k: counts.get(k, 0) for k in OUTCOMES},
                  "stages": {f"{s}:{o}": n for (s, o), n in sorted(stage_counts.items())},
                  "stage_seconds": {s: round(v, 2) for s, v in sorted(stage_seconds.items())},
                  "slowest": [{"case": c, "seconds": s} for s, c in sorted(slowest, reverse=True)[:10]],
                  "slow_s": slow_s, "slow": slow,
                  "findings": findings}
        _write_json(str(out / "summary.json"), record)  # after every case: a stopped campaign keeps its count
        return record

    # SIGTERM or Ctrl-C ends the campaign between cases: the running ones are killed (not counted)
    # and the summary of the finished ones stays.
    stop: list[int] = []
    previous = {sig: signal.signal(sig, lambda number, frame: stop.append(number))
                for sig in (signal.SIGTERM, signal.SIGINT)}
    number = 0
    try:
        while (number < total or running) and not stop:
            while number < total and len(running) < jobs and not stop:
                start(number)
                number += 1
            _wait_any(running, time_limit, finish, stop)
            summary()
            if not quiet and sum(counts.values()) % 100 == 0:
                print(f"{sum(counts.values())} cases, {dict(counts)}", flush=True)
    finally:
        for run in running.values():
            with contextlib.suppress(ProcessLookupError):
                os.kill(run.pid, signal.SIGKILL)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(run.pid, 0)
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        shutil.rmtree(work, ignore_errors=True)
    return summary()


def _warm_up(work: Path) -> None:
    """Run every stage and command once on the simple pendulum, here, before the first fork.

    `lagrangian` loads its subpackages (SymPy, SciPy, the parsers, the printers) on first use;
    paid once here, the forked cases share them instead of each paying seconds for them.
    """
    folder = work / "warm-up"
    folder.mkdir()
    shutil.copyfile(EXAMPLES / "simple_pendulum.toml", folder / "model.toml")
    with open(os.devnull, "w") as null, contextlib.redirect_stdout(null), contextlib.redirect_stderr(null):
        for command in COMMANDS:
            run_case(str(folder / "model.toml"), str(folder), command, str(folder / "result.json"))
    shutil.rmtree(folder, ignore_errors=True)


def _what(record: dict) -> str:
    for entry in record.get("stages", []):
        if entry["outcome"] in BAD:
            lines = [line for line in entry.get("message", "").strip().splitlines() if line.strip()]
            return (lines[-1] if lines else entry.get("type", ""))[:200]
    return (record.get("signal") and f"signal {record['signal']}") or record.get("stderr_tail", "")[-200:]


def _wait_any(running: dict[int, Running], time_limit: float, finish, stop: list) -> None:
    """Wait until one case ends or passes the time cap (then kill it: a hang), or the campaign is stopped."""
    deadline = min(r.start for r in running.values()) + time_limit
    while running and not stop:
        pid, status = os.waitpid(-1, os.WNOHANG)
        if pid and pid in running:
            finish(running.pop(pid), status)
            return
        now = time.monotonic()
        for run in running.values():
            if not run.killed and now - run.start > time_limit:
                run.killed = True
                with contextlib.suppress(ProcessLookupError):
                    os.kill(run.pid, signal.SIGKILL)
        select.select([], [], [], 0.01 if now < deadline else 0.05)


def print_summary(summary: dict) -> None:
    print(f"{summary['cases']} cases (of {summary['planned']} planned) in {summary['seconds']} s (seed {summary['seed']}, time cap "
          f"{summary['time_limit_s']} s, memory cap {summary['memory_gib']} GiB)")
    for outcome in OUTCOMES:
        print(f"  {outcome:<10} {summary['outcomes'][outcome]}")
    if summary["slow"]:
        print(f"  over {summary['slow_s']} s (not defects; kept under findings/ to replay): {len(summary['slow'])}")
    if summary["findings"]:
        print("findings:")
        for f in summary["findings"][:50]:
            print(f"  {f['file']}: {f['outcome']} in {f['stage']}: {f['what']}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="Exit status: 0 when no case is a defect, 1 otherwise.")
    parser.add_argument("--cases", type=int, default=200, help="number of mutated models (default 200)")
    parser.add_argument("--seed", type=int, default=0, help="random seed: the same seed makes the same cases")
    parser.add_argument("--jobs", type=int, default=1, help="cases run at once (default 1)")
    parser.add_argument("--time-limit", type=float, default=30.0, help="seconds per case before it is a hang")
    parser.add_argument("--slow", type=float, default=10.0,
                        help="a case longer than this (s) is kept under findings/slow-*.toml (default 10)")
    parser.add_argument("--memory", type=float, default=4.0, help="memory cap per case, GiB (default 4)")
    parser.add_argument("--example", action="append", help="mutate only this example (repeatable)")
    parser.add_argument("--exclude", action="append", default=[], help="do not mutate this example (repeatable)")
    parser.add_argument("--format", dest="model_format", choices=("toml", "urdf"), default="toml",
                        help="mutate the TOML examples (default) or the URDF robots of examples/*.urdf")
    parser.add_argument("--out", type=Path, default=Path("fuzz-out"), help="folder for the summary and findings")
    parser.add_argument("--replay", nargs="+", type=Path, help="run these model files instead of mutations")
    parser.add_argument("--show-case", type=int, metavar="N",
                        help="print case N of the campaign of this --seed and --out (--example/--exclude/--format as "
                             "it had them) and run nothing")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    if args.show_case is not None:
        text, meta = show_case(args.seed, args.show_case, args.out, examples=args.example, exclude=args.exclude,
                               model_format=args.model_format)
        print(json.dumps(meta), file=sys.stderr)
        sys.stdout.write(text)
        return 0
    summary = campaign(args.cases, args.seed, args.out, jobs=args.jobs, time_limit=args.time_limit,
                       memory_gib=args.memory, examples=args.example, exclude=args.exclude, quiet=args.quiet,
                       replay=args.replay, model_format=args.model_format, slow_s=args.slow)
    print_summary(summary)
    return 1 if any(summary["outcomes"][k] for k in BAD) else 0


if __name__ == "__main__":
    sys.exit(main())
