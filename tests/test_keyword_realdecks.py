"""Public LS-DYNA decks (../shared/realdecks, beside the clone; skipped when absent) read as far as
the keyword reader's part goes (issue 33): the LS-OPT car's *PARAMETER thicknesses, its
*ELEMENT_SHELL_THICKNESS and its contacts with their 0.0 fields; the beer can, copied without its
*CONTROL_IMPLICIT_* cards, read with its *LOAD_NODE_POINT loads acting and run for a short time."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn.keyword.keywords import collect
from paradyn.keyword.reader import read_keyword_file
from paradyn.keyword.scene import load_keyword

REALDECKS = Path(__file__).resolve().parents[1].parent / "shared" / "realdecks"
needs = pytest.mark.skipif(not REALDECKS.is_dir(), reason="../shared/realdecks is not beside the clone")


@needs
def test_the_car_reads_its_parameters_element_thicknesses_and_contacts() -> None:
    """main.k's `r  tbumper 3 rthood 1` parameters give the sections' &tbumper, &thood fields; the
    rigid part's 590 shells carry 0.2 in *ELEMENT_SHELL_THICKNESS; its two *CONTACT_SINGLE_SURFACE_ID
    with every field 0.0 read as LS-DYNA's defaults, none warned."""
    data = collect(read_keyword_file(REALDECKS / "lsopt_car5" / "main.k"))
    assert [data.sections[s][1]["T1"] for s in (2, 3, 4, 5)] == [3.0, 1.0, 1.0, 1.0]
    assert len(data.elements) == 1174
    assert sum(1 for e in data.elements if e.values.get("THIC1") == 0.2) == 590
    assert len(data.contacts) == 2
    for _, cards in data.contacts:
        assert (cards[3]["SFS"], cards[3]["SFST"], cards[2]["DT"]) == (1.0, 1.0, 1e20)
    assert not [w for w in data.warnings if "CONTACT" in w and "is not supported and ignored" in w]


def _explicit_beer_can(tmp_path: Path, end_time: str, curve_time_scale: str = "1.0") -> Path:
    """The beer can deck and its mesh copied to tmp_path without the *CONTROL_IMPLICIT_* keywords,
    with ENDTIM replaced and the load curve's abscissa scaled by ``curve_time_scale`` (SFA)."""
    source = REALDECKS / "pydyna_beer_can"
    blocks = re.split(r"(?m)^(?=\*)", (source / "beer_can.k").read_text())
    text = "".join(b for b in blocks if not b.startswith("*CONTROL_IMPLICIT"))
    text = text.replace("       1.0         0       0.0       0.0     1e+08", f"{end_time:>10}         0       0.0"
                                                                             f"       0.0     1e+08")
    sfa = "         1         0       1.0       1.0       0.0       0.0         0         0"
    assert sfa in text
    text = text.replace(sfa, f"{1:>10}{0:>10}{curve_time_scale:>10}" + sfa[30:])
    (tmp_path / "beer_can.k").write_text(text)
    (tmp_path / "mesh.k").write_text((source / "mesh.k").read_text())
    return tmp_path / "beer_can.k"


@needs
def test_the_beer_can_runs_explicitly_with_its_point_loads(tmp_path: Path) -> None:
    """Without *CONTROL_IMPLICIT_*, the can reads: each *LOAD_NODE_POINT is one ramp of SF over the
    curve's 1 s, the mortar contact is read as automatic single surface (warned), ELFORM -16 is the fully
    integrated element;
    run to 0.5 ms (about 2100 steps), every loaded node has moved down, along its load."""
    read = load_keyword(_explicit_beer_can(tmp_path, "0.0005"))
    model = read.model
    n_loads = len(set(model.load_node.tolist()))
    assert n_loads == model.load_node.size > 20
    assert set(model.load_dof.tolist()) == {3} and set(model.load_value.tolist()) == {-13.1579}
    assert set(model.load_ramp_time.tolist()) == {1.0}
    text = "\n".join(read.warnings)
    assert "(mortar) is read as *CONTACT_AUTOMATIC_SINGLE_SURFACE" in text
    assert "ELFORM" not in text and set(model.shell_element.tolist()) == {2}
    assert [c.kind for c in read.scene.contacts] == ["single_surface"]
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=2, post=False)
    assert res.complete
    dz = res.displacement[-1][model.load_node, 2]
    assert np.all(dz < 0.0)


@needs
@pytest.mark.slow
def test_the_beer_can_buckles_above_the_classical_load(tmp_path: Path) -> None:
    """The can (R = 1.5, t = 0.002, E = 1e7, nu = 0.33: the deck's inch-lbf-s numbers, read as they
    are; ELFORM -16: the fully integrated element) under its 76 nodal loads of 13.1579 each, ramped
    over 20 ms instead of the deck's 1 s (SFA = 0.02: 400 of the can's axial periods, still
    quasi-static; the 1 s ramp is 4.2 M steps). The support's reaction (history reaction_force)
    follows the applied load P(t) to 5 % (the ramp's start rings about 3 %) until 0.8 of the
    classical buckling load of an axially compressed cylinder, P_cl = 2 pi E t^2 / sqrt(3 (1 - nu^2))
    = 153.7 (Timoshenko and Gere, Theory of Elastic Stability, 1961, sec. 11.4); it peaks above P_cl
    (measured 1.63 P_cl at 5.0 ms; 1.18 with the one-point element): the mesh, 0.12 to 0.17 wide,
    is coarser than the classical axisymmetric half-wave 1.72 sqrt(R t) = 0.094, so it cannot take the
    classical mode and buckles higher; a locking element would go far higher, so the peak is bounded
    by 2 P_cl. By 5.3 ms the can has buckled: the reaction falls below 0.9 of the load. Run on, the
    collapsing can crushes an element at 5.46 ms (the deck's load is a force that keeps pushing)."""
    read = load_keyword(_explicit_beer_can(tmp_path, "0.0053", curve_time_scale="0.02"))
    res = paradyn.run(read.model, tmp_path / "run", ranks=1, threads=2, post=False)
    assert res.complete
    t = res.history["time"]
    applied = 76 * 13.1579 * t / 0.02
    reaction = res.history["reaction_force"][:, 2]
    classical = 2.0 * np.pi * 1.0e7 * 0.002**2 / np.sqrt(3.0 * (1.0 - 0.33**2))
    early = (applied > 0.1 * classical) & (applied < 0.8 * classical)
    assert early.sum() > 10
    assert np.allclose(reaction[early], applied[early], rtol=0.05)   # the ramp start rings about 3 %
    peak = int(np.argmax(reaction))
    assert 1.0 * classical < reaction[peak] < 2.0 * classical, reaction[peak] / classical
    assert reaction[-1] < 0.9 * applied[-1]
