"""Titles and captions in the report's language: the course's French words, never an empty caption."""

from __future__ import annotations

import pytest

from lagrangian.plotting import KINDS, applicable_kinds, figure_caption, plot_trajectory


@pytest.mark.parametrize("lang", ["fr", "en"])
def test_every_kind_has_a_caption(run, lang):
    eom, _ = run("lagrange_top.toml")
    captions = [figure_caption(kind, eom, lang) for kind in KINDS]
    assert all(c.strip() for c in captions) and len(set(captions)) == len(KINDS)
    if lang == "fr":
        assert "Trajectoire de l'apex sur la sphère unité" in captions
        assert "Réaction R_O(t)" in captions
        assert any("intégrales premières" in c for c in captions)


def _titles(fig) -> str:
    parts = [fig._suptitle.get_text() if fig._suptitle is not None else ""]
    parts += [ax.get_title() for ax in fig.axes] + [ax.get_ylabel() for ax in fig.axes]
    return "\n".join(parts)


def test_french_titles(run):
    eom, traj = run("lagrange_top.toml")
    kinds = applicable_kinds(traj, eom)
    assert {"apex_sphere", "nutation", "reaction"} <= set(kinds)
    titles = {kind: _titles(plot_trajectory(traj, eom, kind, lang="fr")) for kind in kinds}
    assert "sur la sphère unité" in titles["apex_sphere"]
    assert "vu de dessus" in titles["nutation"]
    assert "réaction au point fixe O" in titles["reaction"]
    assert "dérive relative des intégrales premières" in titles["drift"]
    assert "portraits de phase" in titles["phase"]
    for kind, text in titles.items():
        for english in ("unit sphere", "seen from above", "relative drift", "phase portraits", "reaction at"):
            assert english not in text, (kind, english)
