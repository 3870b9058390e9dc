"""Every command takes a model file, ``zoo:NAME[:N]``, or nothing (the seed's top)."""

from __future__ import annotations

import pytest

import lagrangian
from lagrangian.cli._source import load_source
from lagrangian.cli.main import main
from lagrangian.model import zoo


def test_zoo_names_build_the_zoo_models():
    assert load_source("zoo:planar_chain:3") == zoo.planar_chain(3)
    assert load_source("zoo:spatial_chain:2") == zoo.spatial_chain(2)
    assert load_source("zoo:lagrange_top") == zoo.lagrange_top() == load_source(None)


@pytest.mark.parametrize("name, words", [
    ("zoo:nope", "the zoo has no model `nope`"),
    ("zoo:planar_chain", "needs a number of links"),
    ("zoo:planar_chain:0", "needs a number of links"),
    ("zoo:lagrange_top:3", "takes no size"),
])
def test_bad_zoo_names_are_explained(name, words):
    with pytest.raises(lagrangian.ModelError, match=words):
        load_source(name)


@pytest.mark.parametrize("argv", [["derive", "zoo:planar_chain:2"], ["verify", "zoo:planar_chain:2"],
                                  ["simulate", "zoo:planar_chain:2", "--t-end", "0.1"], ["analyse", "zoo:lagrange_top"]])
def test_every_command_takes_a_zoo_model(argv, capsys):
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert ("planar" in out.lower() or "θ1" in out or "theta1" in out) if "planar" in argv[1] else "θ1" in out


def test_a_bad_zoo_name_exits_with_the_model_error_code(capsys):
    assert main(["derive", "zoo:nope"]) == 2
    assert "zoo:planar_chain:N" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["zoo:planar_chain:²", "zoo:planar_chain:١٢", "zoo:planar_chain:101",
                                  "zoo:spatial_chain:1000", "zoo:planar_chain:" + "9" * 5000,
                                  "zoo:planar_chain:+3", "zoo:planar_chain: 3"])
def test_zoo_sizes_are_plain_digits_up_to_the_limit(name, capsys):
    # `²` once gave a ValueError traceback and N had no upper bound
    with pytest.raises(lagrangian.ModelError, match=f"from 1 to {zoo.MAX_LINKS}") as info:
        load_source(name)
    assert len(str(info.value)) < 300
    assert main(["derive", name]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "from 1 to 100" in err


def test_the_zoo_chains_refuse_too_many_links():
    for make in (zoo.planar_chain, zoo.spatial_chain):
        with pytest.raises(ValueError, match="from 1 to 100"):
            make(zoo.MAX_LINKS + 1)
