"""Problem files: the shipped examples read and solve; mistakes are named with the file and the line."""

from pathlib import Path

import pytest

pytest.importorskip("casadi")

from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.errors import ModelError, ProblemError
from lagrangian.optimal import Problem, load_problem, optimize
from lagrangian.optimal._file import parse_problem

PROBLEMS = sorted((EXAMPLES_DIR / "optimal").glob("*.toml"))


def test_the_examples_are_the_five_problems_the_documentation_lists():
    assert {p.stem for p in PROBLEMS} == {"pendulum_swing_up", "cart_pole_swing_up", "double_pendulum_cart_swing_up",
                                          "acrobot_swing_up", "satellite_slew"}


@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.stem)
def test_every_example_problem_reads_and_solves_on_a_coarse_mesh(path):
    problem = load_problem(path)
    assert isinstance(problem, Problem) and Path(problem.model).exists()
    # a coarse mesh keeps the test short; the files' own meshes are run by the benchmarks and the docs
    best = optimize(problem, nodes=min(problem.nodes, 30), verify=False, max_iterations=500)
    assert best.status in ("optimal", "acceptable"), (path.name, best.status)


GOOD = """
[problem]
model = "{model}"
t_end = 3.0
nodes = 20

[initial]
theta = 0
theta_dot = 0

[final]
theta = "pi"
theta_dot = 0

[bounds]
tau = [-5, 5]
"""


def _problem(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "problem.toml"
    path.write_text(text.replace("{model}", str(EXAMPLES_DIR / "torque_pendulum.toml")), encoding="utf-8")
    return path


def test_a_written_problem_solves_and_its_model_path_is_relative_to_the_file(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "p.toml").write_text((EXAMPLES_DIR / "torque_pendulum.toml").read_text(encoding="utf-8"),
                                                encoding="utf-8")
    path = tmp_path / "problem.toml"
    path.write_text(GOOD.replace("{model}", "models/p.toml"), encoding="utf-8")
    best = optimize(load_problem(path), verify=False)
    assert best.status == "optimal" and best.nodes == 20


@pytest.mark.parametrize("edit, line, message", [
    (("[bounds]", "[limits]"), 15, "unknown table `[limits]`"),
    (("nodes = 20", "nodes = 20\nsteps = 3"), 6, "unknown key `steps` in [problem]"),
    (("tau = [-5, 5]", "tau = [5, -5]"), 16, "bounds of `tau` are reversed"),
    (("tau = [-5, 5]", "torque = [-5, 5]"), 16, "names `torque`"),
    (("tau = [-5, 5]", "tau = 5"), 16, "must be a pair"),
    (('theta = "pi"', 'theta = "pi +"'), 12, "the final value of `theta`"),
    (("nodes = 20", "nodes = 1"), None, "at least 2 nodes"),
    (("t_end = 3.0", "t_end = 3.0 3"), 4, "TOML syntax error"),
    (("t_end = 3.0\n", ""), None, "needs `t_end`"),
])
def test_a_mistake_is_named_with_the_file_and_the_line(tmp_path, edit, line, message):
    path = _problem(tmp_path, GOOD.replace(*edit))
    with pytest.raises(ProblemError, match=message.replace("[", r"\[").replace("(", r"\(")) as caught:
        optimize(load_problem(path), verify=False)
    assert caught.value.file == str(path)
    if line is not None:
        assert caught.value.line == line, caught.value


def test_a_missing_file_and_a_missing_model_are_said(tmp_path):
    with pytest.raises(ProblemError, match="does not exist"):
        load_problem(tmp_path / "nowhere.toml")
    path = tmp_path / "problem.toml"
    path.write_text(GOOD.replace("{model}", "no_model.toml"), encoding="utf-8")
    with pytest.raises(ModelError, match="does not exist"):
        optimize(load_problem(path))


def test_text_is_read_by_the_grammar_never_evaluated(tmp_path):
    path = _problem(tmp_path, GOOD.replace('theta = "pi"', 'theta = "__import__(\'os\').getcwd()"'))
    with pytest.raises(ProblemError):
        optimize(load_problem(path))
    assert parse_problem(GOOD.replace("{model}", "m.toml")).final["theta"] == "pi"
