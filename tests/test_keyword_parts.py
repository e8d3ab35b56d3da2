"""Keyword parts, contacts, defaults and messages (issue 33, items 1, 3, 4, 5; docs/keyword.md):
*ELEMENT_SHELL_THICKNESS split into one engine part per thickness, ELFORM 16 warned and 2-D forms
refused, the contact variants and options, fields whose 0.0 means LS-DYNA's default, and messages
in the deck's own ids. Each deck is the small plate of tests/test_keyword.py with cards added."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from paradyn.keyword.defaults import ZERO_MEANS_DEFAULT, zero_defaults
from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import load_keyword
from test_keyword import HEAD, MESH

THICK_MESH = MESH.replace("*ELEMENT_SHELL\n", "*ELEMENT_SHELL_THICKNESS\n").replace(
    "     101       1      11      12      15      14\n",
    "     101       1      11      12      15      14\n" + "           0.000" * 4 + "\n").replace(
    "     102       1      12      13      16      15\n",
    "     102       1      12      13      16      15\n" + "           0.003" * 4 + "\n")
THIRD = ("*NODE\n      17             3.0             0.0             0.0\n      18             3.0             0.5"
         "             0.0\n*ELEMENT_SHELL_THICKNESS\n     103       1      13      17      18      16\n"
         "           0.003           0.003           0.004           0.004\n")


def _read(tmp_path: Path, extra: str, head: str = HEAD, mesh: str = MESH):
    path = tmp_path / "model.k"
    path.write_text(head + mesh + extra + "*END\n")
    return load_keyword(path)


def test_element_thicknesses_split_a_part_keeping_its_pid(tmp_path: Path) -> None:
    """Element 101 takes the section's 2 mm (THIC 0.0), 102 its own 3 mm, 103 the mean of 3, 3, 4, 4
    mm (warned once): part 1 runs as three engine parts with PID 1, named plate_t<thickness>; a
    single-surface contact on part 1 and a velocity on part 1 take all three."""
    extra = (THIRD + "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         1         0         3\n"
             "*INITIAL_VELOCITY_GENERATION\n         1         2       0.0       1.0\n")
    read = _read(tmp_path, extra, mesh=THICK_MESH)
    model = read.model
    assert model.thickness.tolist() == [0.002, 0.003, 0.0035]
    assert model.element_part.tolist() == [0, 1, 2] and model.part_ids.tolist() == [1, 1, 1]
    assert model.part_names == ["plate_t0.002", "plate_t0.003", "plate_t0.0035"]
    assert model.element_ids.tolist() == [101, 102, 103]
    assert read.scene.contacts[0].parts == ("plate_t0.002", "plate_t0.003", "plate_t0.0035")
    assert np.count_nonzero(model.initial_velocity[:, 0]) == model.n_nodes - 1    # node 12 is fixed
    corner = [w for w in read.warnings if "different corner thicknesses" in w]
    assert len(corner) == 1 and "*ELEMENT_SHELL_THICKNESS 103" in corner[0]
    assert any("*PART 1 has shells of 3 thicknesses (0.002, 0.003, 0.0035)" in w for w in read.warnings)


def test_one_element_thickness_for_a_whole_part_is_its_thickness(tmp_path: Path) -> None:
    """A section of thickness 0 whose elements all give 3 mm: one part of 3 mm, its plain name."""
    mesh = THICK_MESH.replace("           0.000" * 4, "           0.003" * 4)
    model = _read(tmp_path, "", head=HEAD.replace("     0.002" * 4, "       0.0" * 4), mesh=mesh).model
    assert model.thickness.tolist() == [0.003] and model.part_names == ["plate"]
    with pytest.raises(KeywordError, match="101 of part 1 has no thickness"):
        _read(tmp_path, "", head=HEAD.replace("     0.002" * 4, "       0.0" * 4), mesh=THICK_MESH)


def test_shell_formulations(tmp_path: Path) -> None:
    """ELFORM -16 is the fully integrated element with the warping correction; ELFORM 13 (2-D
    plane strain) is refused naming the part and the fix."""
    read = _read(tmp_path, "", head=HEAD.replace("         1         2   ", "         1       -16   "))
    assert not any("ELFORM" in w for w in read.warnings)
    assert read.model.shell_element.tolist() == [2] and read.scene.parts[0].element == "full"
    assert read.model.warping_correction.tolist() == [1]
    with pytest.raises(KeywordError, match=r"\*PART 1 'plate' uses \*SECTION_SHELL 1 ELFORM = 13 \(2-D plane "
                                           r"strain\).*give the section ELFORM 2"):
        _read(tmp_path, "", head=HEAD.replace("         1         2   ", "         1        13   "))


def test_zero_means_the_default(tmp_path: Path) -> None:
    """SLSFAC 0.0 is 0.1 and SFS, SFM, SFST, SFMT, FSF, VSF 0.0 are 1 (the penalty scale 0.1), DT
    0.0 is no death time, QM 0.0 is 0.1, NIP 0 is 2: read as the defaults, none of them warned."""
    extra = ("*CONTROL_CONTACT\n       0.0\n*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         0         0         5\n"
             "       0.0       0.0       0.0       0.0       0.0         0       0.0       0.0\n"
             + "       0.0" * 8 + "\n*HOURGLASS\n         4         4       0.0\n")
    head = HEAD.replace("         1         1         1\n", "         1         1         1         0         4\n")
    read = _read(tmp_path, extra, head=head.replace("         1         2                   3",
                                                    "         1         2       0.0         0"))
    model = read.model
    assert model.contact_penalty_scale.tolist() == [0.1]
    assert model.hourglass_coefficient.tolist() == [0.1] and model.integration_points.tolist() == [2]
    assert not [w for w in read.warnings if "is not supported" in w or "death time" in w or "SFM" in w]
    assert zero_defaults("CONTACT_AUTOMATIC_SINGLE_SURFACE_ID")["SFS"] == 1.0
    assert zero_defaults("CONTROL_CONTACT")["SLSFAC"] == 0.1 and "SLSFAC" not in zero_defaults("CONTACT_X")
    assert len({(z.keyword, z.field) for z in ZERO_MEANS_DEFAULT}) == len(ZERO_MEANS_DEFAULT)


TWO = (MESH + "*NODE\n      17             3.0             0.0             0.0\n"
       "      18             3.0             0.5             0.0\n"
       "*ELEMENT_SHELL\n     103       2      13      17      18      16\n"
       "*PART\nother\n         2         1         1\n")


def test_contact_variants(tmp_path: Path) -> None:
    """Nodes-to-surface: a symmetric pair, warned one-way; mortar: the automatic kind, warned; the
    _ID heading names the contact; BT and DT are the contact's birth and death times; SSID 0
    takes the parts with shells only; a tied contact is a tied pair, slave first."""
    extra = ("*CONTACT_NODES_TO_SURFACE_ID\n         5bolt\n         1         2         3         3\n"
             "       0.2       0.1       0.0       0.0       0.0         0    0.0001    0.0005\n"
             "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR\n         0         0         5         5\n"
             "*CONTACT_TIED_NODES_TO_SURFACE_OFFSET\n         2         1         3         3\n")
    read = _read(tmp_path, extra + "*PART\nshell-less\n         3         1         1\n", mesh=TWO)
    specs = read.scene.contacts
    assert [(c.parts, c.kind, c.symmetric) for c in specs] == [
        (("plate", "other"), "node_to_segment", True), (("plate", "other"), "node_to_segment", True),
        (("other", "plate"), "tied", specs[2].symmetric)]
    assert specs[0].static_friction == 0.2 and specs[0].dynamic_friction == 0.1
    text = "\n".join(read.warnings)
    assert "*CONTACT_NODES_TO_SURFACE 5 'bolt' is one-way in LS-DYNA" in text
    assert (specs[0].birth_time, specs[0].death_time) == (pytest.approx(1e-4), pytest.approx(5e-4))
    assert (specs[1].birth_time, specs[1].death_time) == (0.0, 1e20)   # blank BT, DT: the whole run
    assert "BT = " not in text and "DT = " not in text
    assert "(mortar) is read as *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE" in text


def test_part_contact_friction_for_fs_minus_one(tmp_path: Path) -> None:
    """FS = -1 takes the part's FS, FD, DC from *PART_CONTACT."""
    head = HEAD.replace("*PART\nplate\n         1         1         1\n",
                        "*PART_CONTACT\nplate\n         1         1         1\n       0.3      0.25\n")
    extra = "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         1         0         3\n      -1.0\n"
    spec = _read(tmp_path, extra, head=head).scene.contacts[0]
    assert (spec.static_friction, spec.dynamic_friction) == (0.3, 0.25)


def test_spc_set_id_reads_each_id_card_with_its_constraint(tmp_path: Path) -> None:
    extra = ("*BOUNDARY_SPC_SET_ID\n         1first\n         4         0         1\n"
             "         2second\n         5         0         0         0         1\n"
             "*SET_NODE_LIST\n         4\n        11\n*SET_NODE_LIST\n         5\n        13\n")
    fixed = _read(tmp_path, extra).model.fixed_dofs
    assert fixed[0].tolist() == [1, 0, 0, 0, 0, 0] and fixed[2].tolist() == [0, 0, 1, 0, 0, 0]


def test_model_errors_name_the_decks_ids(tmp_path: Path) -> None:
    """A duplicated element is named by its EID and line, and the earlier one by its EID, not by
    0-based rows; the warnings before the error come with it."""
    mesh = MESH + "*ELEMENT_SHELL\n     207       1      12      13      16      15\n*DATABASE_RWFORC\n"
    with pytest.raises(KeywordError) as refused:
        _read(tmp_path, "", mesh=mesh)
    message = str(refused.value)
    assert "*ELEMENT_SHELL 207 (" in message and "has the same nodes as *ELEMENT_SHELL 102 (" in message
    assert "with nodes [12, 13, 16, 15]" in message and "/elements/connectivity[" not in message
    assert "*DATABASE_RWFORC is not supported" in message.split("warnings before this error")[1]
