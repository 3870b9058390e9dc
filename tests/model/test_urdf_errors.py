"""Bad URDF files: each refused with a `ModelError` naming the file, the line, the element and the fix.

The line expected is found by searching the file's text for a marker, so each case says
which element is meant; the command line prints the same error, with no traceback.
"""

from __future__ import annotations

import pytest

import lagrangian
from lagrangian import ModelError
from lagrangian.cli.main import main
from lagrangian.model.urdf import parse_urdf

LINK = ('<link name="{name}"><inertial><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>')
JOINT = ('<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
         '<axis xyz="0 0 1"/></joint>')


def robot(*parts: str) -> str:
    return '<?xml version="1.0"?>\n<robot name="r">\n' + "\n".join(parts) + "\n</robot>\n"


def ok_parts() -> list[str]:
    return ['<link name="base"/>', LINK.format(name="a"), JOINT.format(name="j1", parent="base", child="a")]


def line_of(text: str, marker: str) -> int:
    return text[:text.index(marker)].count("\n") + 1


CASES = {
    "missing inertia": (robot('<link name="base"/>', '<link name="a"><inertial><mass value="2"/>\n</inertial></link>',
                              JOINT.format(name="j1", parent="base", child="a")),
                        '<inertial><mass value="2"', "has no <inertia>"),
    "non-positive mass": (robot('<link name="base"/>', '<link name="a"><inertial>\n<mass value="-1"/><inertia ixx="1" '
                                'ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>',
                                JOINT.format(name="j1", parent="base", child="a")),
                          '<mass value="-1"', "must be positive"),
    "zero mass with inertia": (robot('<link name="base"/>', '<link name="a"><inertial>\n<mass value="0"/><inertia '
                                     'ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>',
                                     JOINT.format(name="j1", parent="base", child="a")),
                               '<mass value="0"', "must be positive"),
    "indefinite inertia": (robot('<link name="base"/>', '<link name="a"><inertial><mass value="1"/>\n<inertia '
                                 'ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>',
                                 JOINT.format(name="j1", parent="base", child="a")),
                           '<inertia ixx="1" ixy="2"', "not positive semi-definite"),
    "triangle inequality": (robot('<link name="base"/>', '<link name="a"><inertial><mass value="1"/>\n<inertia '
                                  'ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/></inertial></link>',
                                  JOINT.format(name="j1", parent="base", child="a")),
                            '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"', "triangle inequality"),
    "zero-length axis": (robot('<link name="base"/>', LINK.format(name="a"), '<joint name="j1" type="revolute">'
                               '<parent link="base"/><child link="a"/>\n<axis xyz="0 0 0"/></joint>'),
                         '<axis xyz="0 0 0"', "has length 0"),
    "cycle": (robot(LINK.format(name="a"), LINK.format(name="b"), JOINT.format(name="j1", parent="a", child="b"),
                    JOINT.format(name="j2", parent="b", child="a")),
              '<joint name="j1"', "form a cycle"),
    "closed loop": (robot('<link name="base"/>', LINK.format(name="a"), LINK.format(name="b"), LINK.format(name="c"),
                          JOINT.format(name="j1", parent="base", child="a"),
                          JOINT.format(name="j2", parent="base", child="b"),
                          JOINT.format(name="j3", parent="a", child="c"),
                          JOINT.format(name="j4", parent="b", child="c")),
                    '<joint name="j4"', "closed loop"),
    "floating joint below a moving link": (
        robot('<link name="base"/>', LINK.format(name="a"), LINK.format(name="b"),
              JOINT.format(name="j1", parent="base", child="a"),
              '<joint name="free" type="floating"><parent link="a"/><child link="b"/></joint>'),
        '<joint name="free"', "its parent link `a` moves"),
    "floating link without mass": (
        robot('<link name="base"/>', '<link name="a"/>', LINK.format(name="b"),
              '<joint name="free" type="floating"><parent link="base"/><child link="a"/></joint>',
              JOINT.format(name="j1", parent="a", child="b")),
        '<joint name="free"', "carries no mass"),
    "free link with a zero inertia": (
        robot('<link name="base"/>', '<link name="a"><inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" '
              'iyy="0" iyz="0" izz="0"/></inertial></link>',
              '<joint name="free" type="floating"><parent link="base"/><child link="a"/></joint>'),
        '<joint name="free"', "its inertia at G is zero"),
    "mimic of a planar joint": (
        robot('<link name="base"/>', LINK.format(name="a"), LINK.format(name="b"),
              '<joint name="flat" type="planar"><parent link="base"/><child link="a"/></joint>',
              '<joint name="j2" type="revolute"><parent link="a"/><child link="b"/>\n<mimic joint="flat"/></joint>'),
        '<mimic joint="flat"', "follow the planar joint `flat`"),
    "unknown joint type": (robot('<link name="base"/>', LINK.format(name="a"),
                                 '<joint name="odd" type="ball"><parent link="base"/><child link="a"/></joint>'),
                           '<joint name="odd"', "type `ball`"),
    "duplicate link": (robot(*ok_parts(), LINK.format(name="a")), '<link name="a"><inertial><mass value="1"/>'
                       '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>\n</robot>',
                       "two links are named `a`"),
    "duplicate joint": (robot(*ok_parts(), LINK.format(name="b"), JOINT.format(name="j1", parent="a", child="b")),
                        '<joint name="j1" type="revolute"><parent link="a"/>', "two joints are named `j1`"),
    "unknown parent": (robot('<link name="base"/>', LINK.format(name="a"),
                             '<joint name="j1" type="revolute">\n<parent link="bse"/><child link="a"/></joint>'),
                       '<parent link="bse"/>', "unknown parent link `bse`"),
    "two roots": (robot(*ok_parts(), LINK.format(name="stray")), '<link name="stray"', "both roots"),
    "mimic of unknown joint": (robot(*ok_parts(), LINK.format(name="b"), '<joint name="j2" type="revolute"><parent '
                                     'link="a"/><child link="b"/>\n<mimic joint="nope"/></joint>'),
                               '<mimic joint="nope"', "follows unknown joint `nope`"),
    "bad number": (robot('<link name="base"/>', LINK.format(name="a"), '<joint name="j1" type="revolute"><parent '
                         'link="base"/><child link="a"/>\n<origin xyz="0 0 infinity"/></joint>'),
                   '<origin xyz="0 0 infinity"', "`infinity` is not one"),
    "no mass moved": (robot('<link name="base"/>', '<link name="a"/>',
                            '<joint name="j1" type="revolute">\n<parent link="base"/><child link="a"/></joint>'),
                      '<joint name="j1"', "moves no mass"),
    "not a robot": ('<?xml version="1.0"?>\n<model name="x"/>\n', "<model", "not <robot>"),
    "malformed XML": (robot(*ok_parts(), '<link name="b">'), "</robot>", "not well-formed"),
    "XML bomb": ('<?xml version="1.0"?>\n<!DOCTYPE robot [\n <!ENTITY lol "lol">\n'
                 ' <!ENTITY lol2 "&lol;&lol;&lol;">\n]>\n'
                 '<robot name="&lol2;"/>\n', '<!ENTITY lol "lol">', "declares an entity"),
    "external entity": ('<?xml version="1.0"?>\n<!DOCTYPE robot [\n<!ENTITY secret SYSTEM "file:///etc/passwd">\n]>\n'
                        '<robot name="r">&secret;</robot>\n', "<!ENTITY secret", "declares an entity"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_bad_urdf_is_refused_with_file_line_and_fix(case):
    text, marker, words = CASES[case]
    with pytest.raises(ModelError) as info:
        parse_urdf(text, source="bad.urdf")
    error = info.value
    assert words in error.message, error.message
    assert error.file == "bad.urdf" and error.line == line_of(text, marker), (error.line, line_of(text, marker))
    assert error.fix


def test_the_command_line_prints_the_error_with_its_line_and_no_traceback(tmp_path, capsys):
    text, marker, _ = CASES["zero-length axis"]
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    assert main(["derive", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"bad.urdf:{line_of(text, marker)}: error: the axis of joint `j1` has length 0" in err
    assert '<axis xyz="0 0 0"/>' in err and "tip:" in err and "Traceback" not in err


def test_an_external_dtd_is_never_fetched(tmp_path):
    secret = tmp_path / "secret.dtd"
    secret.write_text('<!ENTITY leak "read">')
    text = (f'<?xml version="1.0"?>\n<!DOCTYPE robot SYSTEM "{secret.as_uri()}">\n'
            + robot(*ok_parts()).split("\n", 1)[1])
    model = parse_urdf(text, source="r.urdf")  # the DTD is not read: nothing of it can reach the model
    assert [c.name for c in model.coordinates] == ["j1"]


def test_odd_and_clashing_names_become_distinct_identifiers():
    text = robot('<link name="g"/>', LINK.format(name="t"), LINK.format(name="arm-1"),
                 JOINT.format(name="t", parent="g", child="t"), JOINT.format(name="arm-1", parent="t", child="arm-1"))
    model = parse_urdf(text, source="r.urdf")
    assert [c.name for c in model.coordinates] == ["t_2", "arm_1"]  # `t` is the time, `arm-1` no identifier
    names = [c.name for c in model.coordinates] + [b.name for b in model.bodies] + list(model.inputs)
    assert len(set(names)) == len(names) and all(n.isidentifier() and n not in ("t", "g", "pi") for n in names)
    assert model.inputs == ("tau_t", "tau_arm_1") and {b.name for b in model.bodies} == {"t_3", "arm_1_2"}


def test_a_robot_with_too_many_joints_is_refused_before_any_derivation():
    parts = ['<link name="l0"/>']
    for k in range(1, 103):
        parts += [LINK.format(name=f"l{k}"), JOINT.format(name=f"j{k}", parent=f"l{k - 1}", child=f"l{k}")]
    text = robot(*parts)
    with pytest.raises(ModelError, match="102 moving joints, more than the 100") as info:
        parse_urdf(text, source="long.urdf")
    assert info.value.line == line_of(text, '<joint name="j101"')


def test_a_huge_file_is_refused_before_it_is_parsed(tmp_path):
    path = tmp_path / "huge.urdf"
    path.write_text(robot(*ok_parts(), "<!--" + "x" * (6 * 2**20) + "-->"))
    with pytest.raises(ModelError, match="more than the 5 MB read"):
        lagrangian.load_urdf(path)


def test_an_offset_whose_huygens_term_overflows_is_refused_with_the_joint(tmp_path) -> None:
    # Found by `tools/fuzz.py --format urdf` (seed 201, case 577): a fixed joint's origin 1e308 m
    # away merges its link with m d² = inf; the reader raised OverflowError in `_number`.
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "examples" / "rrr_arm.urdf").read_text(encoding="utf-8")
    bad = text.replace('<origin xyz="0.4 0 0"/>\n  </joint>\n</robot>', '<origin xyz="0.4 1e308 0"/>\n  </joint>\n</robot>')
    assert bad != text
    path = tmp_path / "arm.urdf"
    path.write_text(bad, encoding="utf-8")
    with pytest.raises(ModelError, match="overflows a double") as info:
        lagrangian.load_model(path)
    assert info.value.line is not None and "origin" in info.value.fix
    assert main(["derive", str(path)]) == 2
