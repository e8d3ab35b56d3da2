"""LS-DYNA keyword input (issue 18, docs/keyword.md): the file format (fixed columns, long and free
format, comments, *INCLUDE, *PARAMETER), the cards of the subset and their mapping to the model,
units, and the warnings and errors. Each deck here is a small plate written out in the test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import _schema
from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import keyword_scene, load_keyword
from paradyn.running import preflight
from paradyn.scene.specs import ContactSpec

HEAD = """*KEYWORD
*CONTROL_TERMINATION
     0.001
*MAT_ELASTIC
         1    7800.0     2e+11       0.3
*SECTION_SHELL
         1         2                   3
     0.002     0.002     0.002     0.002
*PART
plate
         1         1         1
"""
# two elements side by side, 1 m x 0.5 m each, in the fixed columns of *NODE (8, 16, 16, 16, 8, 8)
MESH = """*NODE
      11             0.0             0.0             0.0
      12             1.0             0.0             0.0       7       7
      13             2.0             0.0             0.0
      14             0.0             0.5             0.0
      15             1.0             0.5             0.0
      16             2.0             0.5             0.0
*ELEMENT_SHELL
     101       1      11      12      15      14
     102       1      12      13      16      15
"""


def _deck(tmp_path: Path, text: str, name: str = "model.k") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _model(tmp_path: Path, extra: str = "", head: str = HEAD, mesh: str = MESH) -> paradyn.deck.Model:
    return load_keyword(_deck(tmp_path, head + mesh + extra + "*END\n")).model


# ------------------------------------------------------------------------------------------------
# the file format


def test_fixed_columns_read_nodes_elements_and_cards(tmp_path: Path) -> None:
    read = load_keyword(_deck(tmp_path, HEAD + MESH))
    model = read.model
    np.testing.assert_array_equal(model.coordinates[:, 0], [0.0, 1.0, 2.0, 0.0, 1.0, 2.0])
    np.testing.assert_array_equal(model.connectivity, [[0, 1, 4, 3], [1, 2, 5, 4]])
    assert model.node_ids.tolist() == [11, 12, 13, 14, 15, 16] and model.element_ids.tolist() == [101, 102]
    assert model.youngs_modulus.tolist() == [2e11] and model.thickness.tolist() == [0.002]
    assert model.integration_points.tolist() == [3] and model.part_names == ["plate"]
    assert model.fixed_dofs[1].tolist() == [1] * 6 and model.fixed_dofs[0].tolist() == [0] * 6   # TC = RC = 7
    assert model.control.end_time == 0.001 and model.control.output_interval == pytest.approx(0.001 / 20)


def test_free_format_with_commas_and_blank_entries(tmp_path: Path) -> None:
    """Comma-separated fields in order; an empty entry takes the default (NIP 2 for *SECTION_SHELL)."""
    head = HEAD.replace("         1         2                   3\n", "1,2,,,\n")
    mesh = MESH.replace("      13             2.0             0.0             0.0", "13, 2.0e0 ,0,  0.0")
    model = _model(tmp_path, head=head, mesh=mesh)
    assert model.integration_points.tolist() == [2]
    assert model.coordinates[2].tolist() == [2.0, 0.0, 0.0]


def test_long_format_by_suffix_and_by_keyword_option(tmp_path: Path) -> None:
    """``*NODE +`` reads 20-character fields; ``*KEYWORD LONG=Y`` makes every card long."""
    long_nodes = "*NODE +\n" + "".join(f"{nid:>20}{x:>20}{y:>20}{0.0:>20}\n" for nid, x, y in
                                       [(11, 0.0, 0.0), (12, 1.0, 0.0), (13, 2.0, 0.0), (14, 0.0, 0.5),
                                        (15, 1.0, 0.5), (16, 2.0, 0.5)])
    mesh = long_nodes + MESH[MESH.index("*ELEMENT_SHELL"):]
    assert _model(tmp_path, mesh=mesh).coordinates[5].tolist() == [2.0, 0.5, 0.0]
    widened = "".join(line if line.startswith(("*", "plate")) else
                      "".join(f"{field.strip():>20}" for field in _columns(line)) + "\n"
                      for line in (HEAD + MESH).splitlines(keepends=True))
    model = load_keyword(_deck(tmp_path, widened.replace("*KEYWORD", "*KEYWORD LONG=Y"), "long.k")).model
    assert model.element_ids.tolist() == [101, 102] and model.integration_points.tolist() == [3]


def _columns(line: str) -> list[str]:
    """The fields of a fixed-column line of HEAD or MESH (8-wide ids for nodes and elements)."""
    text = line.rstrip("\n")
    if len(text) >= 56 and text.startswith("      1"):        # a *NODE line
        widths = [8, 16, 16, 16, 8, 8]
    elif text.startswith("     10"):                          # an *ELEMENT_SHELL line
        widths = [8] * 6
    else:
        widths = [10] * ((len(text) + 9) // 10)
    out, start = [], 0
    for width in widths:
        out.append(text[start:start + width])
        start += width
    return out


def test_comments_and_blank_lines_are_skipped(tmp_path: Path) -> None:
    mesh = MESH.replace("*ELEMENT_SHELL\n", "*ELEMENT_SHELL\n$    EID     PID      N1\n\n")
    assert _model(tmp_path, mesh="$ a comment line\n" + mesh).n_elements == 2


def test_parameters_are_substituted(tmp_path: Path) -> None:
    """*PARAMETER R/I names; ``&name`` and ``-&name`` in later fields, real and integer."""
    cards = f"{'R rho':<10}{'7800.0':>10}{'I  nip':<10}{'3':>10}\n{'R    tz':<10}{'-0.25':>10}\n"
    head = HEAD.replace("    7800.0", "      &rho").replace("                   3\n", "                &nip\n")
    head = head.replace("*CONTROL_TERMINATION", "*PARAMETER\n" + cards + "*CONTROL_TERMINATION")
    mesh = MESH.replace("      16             2.0             0.5             0.0",
                        "      16             2.0             0.5            -&tz")
    model = _model(tmp_path, head=head, mesh=mesh)
    assert model.density.tolist() == [7800.0] and model.integration_points.tolist() == [3]
    assert model.coordinates[5, 2] == 0.25


def test_undefined_parameter_names_file_line_and_field(tmp_path: Path) -> None:
    head = HEAD.replace("    7800.0", "      &rho")
    with pytest.raises(KeywordError, match=r"model\.k:5: \*MAT_ELASTIC field RO = '&rho' names no parameter"):
        _model(tmp_path, head=head)


def test_include_is_relative_to_the_including_file(tmp_path: Path) -> None:
    (tmp_path / "mesh").mkdir()
    (tmp_path / "mesh" / "nodes.k").write_text("*KEYWORD\n" + MESH[:MESH.index("*ELEMENT_SHELL")] + "*END\n")
    (tmp_path / "mesh" / "all.k").write_text("*INCLUDE\nnodes.k\n" + MESH[MESH.index("*ELEMENT_SHELL"):])
    model = load_keyword(_deck(tmp_path, HEAD + "*INCLUDE\nmesh/all.k\n*END\n")).model
    assert model.node_ids.tolist() == [11, 12, 13, 14, 15, 16] and model.n_elements == 2


def test_include_cycle_is_an_error(tmp_path: Path) -> None:
    _deck(tmp_path, "*KEYWORD\n*INCLUDE\nmodel.k\n", "other.k")
    with pytest.raises(KeywordError, match="cycle"):
        load_keyword(_deck(tmp_path, HEAD + "*INCLUDE\nother.k\n" + MESH))


@pytest.mark.parametrize("bad, field", [("    7.8e3x", "RO"), ("       nan", "RO"), ("      1.5x", "RO")])
def test_bad_number_names_file_line_and_field(tmp_path: Path, bad: str, field: str) -> None:
    head = HEAD.replace("    7800.0", bad)
    with pytest.raises(KeywordError, match=rf"model\.k:5: \*MAT_ELASTIC field {field} = '{bad.strip()}'"):
        _model(tmp_path, head=head)


def test_bad_integer_names_the_field(tmp_path: Path) -> None:
    mesh = MESH.replace("     102       1", "     102     1.5")
    with pytest.raises(KeywordError, match=r"model\.k:21: \*ELEMENT_SHELL field PID = '1.5' is not an integer"):
        _model(tmp_path, mesh=mesh)


def test_fortran_exponents_are_numbers(tmp_path: Path) -> None:
    head = HEAD.replace("     2e+11", "    2.0d11").replace("    7800.0", "    7.8+03")
    model = _model(tmp_path, head=head)
    assert model.youngs_modulus.tolist() == [2e11] and model.density.tolist() == [7800.0]


# ------------------------------------------------------------------------------------------------
# warnings and errors of the subset


def test_unsupported_keyword_and_field_are_named_with_their_line(tmp_path: Path) -> None:
    extra = "*CONTROL_ACCURACY\n         1\n*CONTROL_TIMESTEP\n   1.0e-07       0.8\n"
    read = load_keyword(_deck(tmp_path, HEAD + MESH + extra))
    text = "\n".join(read.warnings)
    assert "model.k:22: *CONTROL_ACCURACY is not supported by ParaDyn and is ignored" in text
    assert "model.k:25: *CONTROL_TIMESTEP DTINIT = 1e-07 is not supported and ignored" in text
    assert read.model.control.time_step_safety == 0.8
    assert "no *CONTROL_UNITS: the numbers are taken as SI" in text


def test_read_keyword_prints_the_warnings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    paradyn.read_keyword(_deck(tmp_path, HEAD + MESH + "*CONTROL_ACCURACY\n         1\n"))
    err = capsys.readouterr().err
    assert "paradyn: warning:" in err and "*CONTROL_ACCURACY" in err and "units SI" in err


@pytest.mark.parametrize("edit, message", [
    (("      16      15", "      99      15"), "names node 99, which no \\*NODE defines"),
    (("     0.001", "       0.0"), "ENDTIM must be given and positive"),
    (("         1         1         1\n", "         1         1         7\n"), "names material 7"),
    (("      13             2.0", "      12             2.0"), "\\*NODE 12 is defined twice"),
])
def test_deck_errors_name_the_problem(tmp_path: Path, edit: tuple[str, str], message: str) -> None:
    text = (HEAD + MESH).replace(*edit)
    with pytest.raises(KeywordError, match=message):
        load_keyword(_deck(tmp_path, text))


@pytest.mark.parametrize("fourth", ["      15", "       0", ""])
def test_triangles_are_read_as_degenerate_quads(tmp_path: Path, fourth: str) -> None:
    """Reference: LS-DYNA's *ELEMENT_SHELL, where a triangle repeats N3 as N4 (or leaves N4 blank):
    element 102 as 12, 13, 15 becomes a row whose third node is repeated as the fourth (issue 33)."""
    text = (HEAD + MESH).replace("     102       1      12      13      16      15",
                                 "     102       1      12      13      15" + fourth)
    read = load_keyword(_deck(tmp_path, text))
    conn = read.model.connectivity
    assert conn.shape == (2, 4)
    assert conn[1, 2] == conn[1, 3] and len(set(conn[1].tolist())) == 3
    assert conn[0, 2] != conn[0, 3]
    assert read.model.element_ids.tolist() == [101, 102]


def test_triangles_follow_the_quads_of_their_part(tmp_path: Path) -> None:
    """A part's triangles go after its quadrilaterals (geometry.shape_order), their ids with them, so
    that the engine's groups of one part and one shape stay full: 101 as a triangle comes second."""
    text = (HEAD + MESH).replace("     101       1      11      12      15      14",
                                 "     101       1      11      12      15      15")
    read = load_keyword(_deck(tmp_path, text))
    assert read.model.element_ids.tolist() == [102, 101]
    conn = read.model.connectivity
    assert conn[1, 2] == conn[1, 3] and conn[0, 2] != conn[0, 3]


# ------------------------------------------------------------------------------------------------
# mapping to the model


def test_units_are_converted_to_si(tmp_path: Path) -> None:
    """mm, tonne, s (N, MPa): coordinates and thickness in mm, density in t/mm^3, E in MPa."""
    head = (HEAD.replace("    7800.0     2e+11", "    7.8e-9  200000.0").replace("     0.002" * 4, "       2.0" * 4)
            .replace("*CONTROL_TERMINATION", "*CONTROL_UNITS\n        mm       sec  mtrc_ton\n*CONTROL_TERMINATION"))
    mesh = MESH.replace("             1.0 ", "          1000.0 ").replace("             2.0 ", "          2000.0 ")
    mesh = mesh.replace("             0.5 ", "           500.0 ")
    extra = "*INITIAL_VELOCITY_GENERATION\n         1         2       0.0    1000.0\n\n"
    read = load_keyword(_deck(tmp_path, head + mesh + extra))
    model = read.model
    assert model.density[0] == pytest.approx(7800.0) and model.youngs_modulus[0] == pytest.approx(2e11)
    assert model.thickness[0] == pytest.approx(0.002) and model.coordinates[5].tolist() == pytest.approx([2, .5, 0])
    assert model.initial_velocity[0].tolist() == pytest.approx([1.0, 0.0, 0.0])
    assert model.initial_velocity[1].tolist() == [0.0, 0.0, 0.0]     # node 12 is fixed (TC = 7)
    assert any("units mm-t-s" in w for w in read.warnings)
    same = load_keyword(_deck(tmp_path, head.replace("*CONTROL_UNITS\n        mm       sec  mtrc_ton\n", "")
                              + mesh + extra, "plain.k"), units="mm-t-s").model
    np.testing.assert_array_equal(same.density, model.density)


def test_initial_velocity_rotation_and_node_override(tmp_path: Path) -> None:
    """OMEGA about z through (1, 0, 0): v = omega z x (x - c); *INITIAL_VELOCITY_NODE wins for its node."""
    extra = ("*INITIAL_VELOCITY_GENERATION\n         0         2       2.0\n       1.0       0.0       0.0"
             "       0.0       0.0       1.0\n*INITIAL_VELOCITY_NODE\n        16       0.0       0.0       3.0\n")
    model = _model(tmp_path, extra)
    np.testing.assert_allclose(model.initial_velocity[3], [0.0 - 2.0 * 0.5, 2.0 * -1.0, 0.0])  # node 14 at (0, .5)
    np.testing.assert_allclose(model.initial_angular_velocity[3], [0.0, 0.0, 2.0])
    assert model.initial_velocity[5].tolist() == [0.0, 0.0, 3.0]


def test_spc_node_and_set(tmp_path: Path) -> None:
    extra = ("*BOUNDARY_SPC_NODE\n        11         0         1         0         1\n"
             "*SET_NODE_LIST_TITLE\nright edge\n         5\n        13        16\n"
             "*BOUNDARY_SPC_SET\n         5         0         0         1         0         1         1         1\n")
    model = _model(tmp_path, extra)
    assert model.fixed_dofs[0].tolist() == [1, 0, 1, 0, 0, 0]
    assert model.fixed_dofs[2].tolist() == model.fixed_dofs[5].tolist() == [0, 1, 0, 1, 1, 1]


TWO_PARTS = MESH.replace("     102       1", "     102       2") + """*PART
lid
         2         1         1
*SET_PART_LIST
         9
         1         2
"""


def test_surface_to_surface_contact_is_a_symmetric_pair(tmp_path: Path) -> None:
    """SSID/MSID parts or part sets; FS, FD, DC; penalty scale SLSFAC x SFS."""
    extra = ("*CONTROL_CONTACT\n      0.05\n*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_ID\n         3 touch\n"
             "         1         2         3         3\n       0.3       0.2      10.0\n       2.0       2.0\n")
    read = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + extra))
    assert read.scene.contacts == [ContactSpec(parts=("plate", "lid"), penalty_scale=pytest.approx(0.1),
                                               static_friction=0.3, dynamic_friction=0.2, friction_decay=10.0,
                                               symmetric=True)]
    assert read.model.contact_pairs.tolist() == [[0, 1]]
    every = extra.replace("         1         2         3         3", "         0         0         3         3")
    assert len(load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + every, "every.k")).scene.contacts) == 1
    assert read.model.node_ids.tolist() == [11, 12, 13, 14, 15, 16]   # node 12 and 15 shared by both parts


def test_soft_2_reads_as_contact_with_edge_checks(tmp_path: Path) -> None:
    """SOFT = 2 (card A; LS-DYNA's segment-based contact, which finds walls crossing edge against edge)
    gives edges = true: the pair becomes the deck kind edge_to_edge, a single surface
    single_surface_edges (issue 35; docs/keyword.md)."""
    cards = "         1         2         3         3\n       0.3\n\n         2\n"
    pair = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n" + cards))
    assert pair.scene.contacts[0].edges
    kinds = _schema.ENUMS["contact_kind"]
    assert pair.model.contact_kind.tolist() == [kinds["edge_to_edge"]]
    single = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n"
                                "         9         0         2\n       0.1\n\n         2\n", "single.k"))
    assert set(single.model.contact_kind.tolist()) == {kinds["single_surface_edges"], kinds["edge_to_edge"]}
    plain = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n"
                               + cards.replace("         2\n", "         0\n"), "plain.k"))
    assert plain.model.contact_kind.tolist() == [kinds["node_to_segment"]]


def test_single_surface_contact_maps_to_the_single_surface_kind(tmp_path: Path) -> None:
    """*CONTACT_AUTOMATIC_SINGLE_SURFACE on a part set is one contact of kind single_surface over
    its parts; SSID 0 takes every part (no parts, as in a scene)."""
    extra = "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         9         0         2\n       0.1\n"
    path = _deck(tmp_path, HEAD + TWO_PARTS + extra)
    contacts = keyword_scene(path).contacts
    assert [(c.kind, c.parts, c.static_friction) for c in contacts] == [("single_surface", ("plate", "lid"), 0.1)]
    every = keyword_scene(_deck(tmp_path, HEAD + TWO_PARTS + extra.replace("         9         0         2",
                                                                               "         0         0         5"),
                                "all.k")).contacts
    assert every[0].parts == ()
    model = load_keyword(path).model
    kinds = _schema.ENUMS["contact_kind"]
    assert model.contact_pairs.tolist() == [[0, 0], [1, 1], [0, 1]]
    assert model.contact_kind.tolist() == [kinds["single_surface"]] * 2 + [kinds["node_to_segment"]]


def test_hourglass_and_element_formulation(tmp_path: Path) -> None:
    """No hourglass card: LS-DYNA's default IHQ 1 (viscous), 0.1; *HOURGLASS IHQ 4 is the stiffness
    form; ELFORM 2 has no warping correction, ELFORM 10 has it, ELFORM 16 is the fully integrated element
    (/parts/shell_element full), without a warning."""
    plain = _model(tmp_path)
    assert plain.hourglass_form.tolist() == [_schema.ENUMS["hourglass_form"]["viscous"]]
    assert plain.warping_correction.tolist() == [0]
    head = HEAD.replace("         1         2                   3", "         1        10                   3")
    head = head.replace("         1         1         1\n", "         1         1         1         0         4\n")
    model = _model(tmp_path, "*HOURGLASS\n         4         5      0.05\n", head=head)
    assert model.hourglass_form.tolist() == [_schema.ENUMS["hourglass_form"]["stiffness"]]
    assert model.hourglass_coefficient.tolist() == [0.05] and model.warping_correction.tolist() == [1]
    read = load_keyword(_deck(tmp_path, HEAD.replace("         1         2   ", "         1        16   ") + MESH,
                              "e16.k"))
    assert not any("ELFORM" in w for w in read.warnings)
    assert read.model.shell_element.tolist() == [_schema.ENUMS["shell_element"]["full"]]
    assert plain.shell_element.tolist() == [_schema.ENUMS["shell_element"]["blt"]]


def test_time_step_cap_mass_scaling_and_history_nodes(tmp_path: Path) -> None:
    extra = ("*CONTROL_TIMESTEP\n       0.0       0.8         0       0.0   -2.0e-6         7\n"
             "*DEFINE_CURVE\n         7\n                 0.0               1e-06\n"
             "*DATABASE_BINARY_D3PLOT\n    1.0e-4\n*DATABASE_GLSTAT\n    1.0e-5\n"
             "*DATABASE_HISTORY_NODE\n        13        16\n*DATABASE_HISTORY_NODE_ID\n        11corner\n")
    model = _model(tmp_path, extra)
    c = model.control
    assert (c.time_step, c.time_step_safety, c.output_interval, c.history_interval) == (1e-6, 0.8, 1e-4, 1e-5)
    assert c.mass_scaling_step == pytest.approx(0.8 * 2e-6)
    assert model.tracked_nodes.tolist() == [2, 5, 0] and model.tracked_names == ["node_13", "node_16", "corner"]


def test_single_surface_deck_runs(tmp_path: Path) -> None:
    """End to end: a deck with *CONTACT_AUTOMATIC_SINGLE_SURFACE over every part builds and runs."""
    extra = "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         0         0         5\n"
    head = HEAD.replace("     0.001", "    1.0e-5")
    model = load_keyword(_deck(tmp_path, head + TWO_PARTS + extra)).model
    assert model.n_contacts >= 1
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=1, post=False)
    assert res.history["time"][-1] == pytest.approx(1e-5)


def test_mat3_strain_rate_constants_make_the_rate_member(tmp_path: Path) -> None:
    """*MAT_PLASTIC_KINEMATIC SRC, SRP (Cowper-Symonds C, P) make the material j2_rate with C in
    1/s: mild steel's C = 40.4 1/s, P = 5 (Jones, Structural Impact) in an SI deck and in mm-kg-ms
    (SRC = 0.0404 1/ms); SRC = 0 (blank) is plain J2, as in LS-DYNA."""
    plastic = "*MAT_PLASTIC_KINEMATIC\n         1    7800.0     2e+11       0.3     2.5e8\n{}\n"
    model = _model(tmp_path, head=HEAD.replace("*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n",
                                               plastic.format("      40.4       5.0")))
    assert model.material_model.tolist() == [_schema.ENUMS["material_model"]["j2_rate"]]
    assert model.rate_c.tolist() == [40.4] and model.rate_p.tolist() == [5.0]
    assert model.yield_stress.tolist() == [2.5e8]
    plain = _model(tmp_path, head=HEAD.replace("*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n",
                                               plastic.format("")))
    assert plain.material_model.tolist() == [_schema.ENUMS["material_model"]["j2_plasticity"]]
    with pytest.raises(KeywordError, match=r"SRC = 40\.4, SRP = 0: the Cowper-Symonds constants must both be > 0"):
        _model(tmp_path, head=HEAD.replace("*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n",
                                           plastic.format("      40.4")))
    ms = (HEAD.replace("*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n",
                       plastic.format("    0.0404       5.0").replace("    7800.0     2e+11       0.3     2.5e8",
                                                                      "    7.8e-6     200.0       0.3      0.25"))
          .replace("*CONTROL_TERMINATION\n     0.001", "*CONTROL_UNITS\n        mm        ms        kg\n"
                                                      "*CONTROL_TERMINATION\n       1.0"))
    mesh = MESH.replace("             1.0 ", "          1000.0 ").replace("             2.0 ", "          2000.0 ")
    mesh = mesh.replace("             0.5 ", "           500.0 ")
    model = _model(tmp_path, head=ms.replace("     0.002" * 4, "       2.0" * 4), mesh=mesh)
    assert model.rate_c[0] == pytest.approx(40.4) and model.yield_stress[0] == pytest.approx(2.5e8)


def test_load_body_is_a_base_acceleration_pulling_the_other_way(tmp_path: Path) -> None:
    """*LOAD_BODY_Z with a curve of 9.81 is gravity along -z, as LS-DYNA reads it (a base
    acceleration: the model is pushed against it): the deck's [[base_acceleration]] row points
    along -z with SF as its value and the curve as written; run, the plate held at node 12 sags."""
    extra = ("*LOAD_BODY_Z\n         7       2.0\n"
             "*DEFINE_CURVE\n         7                           0.5\n"
             "                 0.0            9.81\n                 1.0            9.81\n")
    model = _model(tmp_path, extra=extra)
    assert model.base_acceleration_direction.tolist() == [[0.0, 0.0, -1.0]]
    assert model.base_acceleration_value.tolist() == [2.0] and model.base_acceleration_curve.tolist() == [0]
    assert model.curve_time.tolist() == [0.0, 1.0] and model.curve_value.tolist() == [9.81 * 0.5, 9.81 * 0.5]
    assert not any("nothing in this model" in w for w in preflight.check_model(model).warnings)
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=1, post=False)
    z = res.displacement[-1][:, 2]
    assert z.max() <= 0.0 < -z.min()   # every free node went down, none up
    with pytest.raises(KeywordError, match="LCID = 8 names no"):
        _model(tmp_path, extra=extra.replace("*LOAD_BODY_Z\n         7", "*LOAD_BODY_Z\n         8"))
