"""Keyword decks' piecewise-linear plasticity (docs/keyword.md): *MAT_PIECEWISE_LINEAR_PLASTICITY /
*MAT_024 and *MAT_PLASTICITY_WITH_DAMAGE / *MAT_081 read as the piecewise_linear members.

LS-DYNA's MAT 24 card layout (card 1 MID RO E PR SIGY ETAN FAIL TDEL; card 2 C P LCSS LCSR VP;
cards 3 and 4 EPS1..8, ES1..8): the yield curve is LCSS (a *DEFINE_CURVE of stress against
effective plastic strain, SFA and SFO scaling its axes), else the EPS/ES pairs, else the bilinear
law of SIGY and ETAN; rates by LCSR (a curve of the factor against the strain rate), else
Cowper-Symonds C and P (C = 0: none). Each deck is the plate of tests/test_keyword.py with its
material replaced; the real deck of pydyna's ball-and-plate example is read from
../shared/realdecks (skipped where absent)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from paradyn import _schema
from paradyn.keyword.cards import collect
from paradyn.keyword.materials import material_of
from paradyn.keyword.reader import KeywordError, read_keyword_file
from paradyn.keyword.scene import load_keyword
from paradyn.keyword.units import Units

CODES = _schema.ENUMS["material_model"]
HEAD = """*KEYWORD
*CONTROL_TERMINATION
     0.001
{material}*SECTION_SHELL
         1         2                   3
     0.002     0.002     0.002     0.002
*PART
plate
         1         1         1
*NODE
      11             0.0             0.0             0.0
      12             1.0             0.0             0.0
      13             0.0             0.5             0.0
      14             1.0             0.5             0.0
*ELEMENT_SHELL
     101       1      11      12      14      13
"""
REAL_DECK = Path(__file__).resolve().parents[1] / ".." / "shared" / "realdecks" / "pydyna_ball_plate" / "ball_plate.k"


def _card(*values: object) -> str:
    return "".join(f"{v:>10.6g}" if isinstance(v, float) else f"{v:>10}" for v in values) + "\n"


def _mat24(card1: tuple[object, ...] = (1, 7800.0, 2e11, 0.3, 2.5e8, 1e9), card2: tuple[object, ...] = (),
           eps: tuple[object, ...] = (), es: tuple[object, ...] = (), keyword: str = "MAT_024") -> str:
    return f"*{keyword}\n" + _card(*card1) + _card(*card2) + _card(*eps) + _card(*es)


def _read(tmp_path: Path, material: str, extra: str = "") -> tuple[object, list[str]]:
    path = tmp_path / "model.k"
    path.write_text(HEAD.format(material=material) + extra + "*END\n")
    read = load_keyword(path)
    return read.model, read.warnings


def _curve(model: object, index: int) -> tuple[list[float], list[float]]:
    first = [*model.curve_first_point, len(model.curve_time)]
    return (model.curve_time[first[index]:first[index + 1]].tolist(),
            model.curve_value[first[index]:first[index + 1]].tolist())


def test_lcss_is_the_hardening_curve_with_its_scale_factors(tmp_path: Path) -> None:
    """LCSS = 5 with SFO = 1e6 (the curve in MPa): the material's curve holds stresses in Pa and
    starts the material at its first point (SIGY ignored, as in LS-DYNA); a *LOAD_BODY_Z curve read
    beside it keeps its index, the material's curve comes after it."""
    curve = ("*DEFINE_CURVE\n" + _card(5, 0, 1.0, 1e6) + "                 0.0           300.0\n"
             "                 0.1           400.0\n                 0.5           450.0\n")
    body = "*LOAD_BODY_Z\n         7       1.0\n*DEFINE_CURVE\n         7\n                 0.0            9.81\n"
    model, _ = _read(tmp_path, _mat24(card2=(0.0, 0.0, 5)), curve + body)
    assert model.material_model.tolist() == [CODES["piecewise_linear"]]
    assert model.yield_stress.tolist() == [300e6] and model.base_acceleration_curve.tolist() == [0]
    assert model.hardening_curve.tolist() == [1] and model.rate_curve.tolist() == [-1]
    assert _curve(model, 1) == ([0.0, 0.1, 0.5], [300e6, 400e6, 450e6])
    assert _curve(model, 0) == ([0.0, 0.001], [9.81, 9.81])   # a load's curve runs to the end time (ENDTIM)


def test_eps_es_pairs_make_the_curve_up_to_the_last_stress(tmp_path: Path) -> None:
    model, _ = _read(tmp_path, _mat24(card2=(), eps=(0.0, 0.05, 0.2), es=(2.6e8, 3.1e8, 3.5e8)))
    assert model.hardening_curve.tolist() == [0] and model.yield_stress.tolist() == [2.6e8]
    assert _curve(model, 0) == ([0.0, 0.05, 0.2], [2.6e8, 3.1e8, 3.5e8])


def test_without_a_curve_sigy_and_etan_are_bilinear(tmp_path: Path) -> None:
    model, _ = _read(tmp_path, _mat24())
    assert model.material_model.tolist() == [CODES["piecewise_linear"]]
    assert model.hardening_curve.tolist() == [-1]
    assert model.yield_stress.tolist() == [2.5e8] and model.tangent_modulus.tolist() == [1e9]


def test_c_and_p_or_lcsr_scale_the_yield_stress(tmp_path: Path) -> None:
    """C, P: piecewise_linear_rate with mild steel's 40.4 1/s and 5; LCSR: the rate curve (its
    rates in 1/s), and C, P then ignored with a warning; C without P refused."""
    model, _ = _read(tmp_path, _mat24(card2=(40.4, 5.0)))
    assert model.material_model.tolist() == [CODES["piecewise_linear_rate"]]
    assert model.rate_c.tolist() == [40.4] and model.rate_p.tolist() == [5.0]
    rates = "*DEFINE_CURVE\n         9\n                 0.0             1.0\n               100.0             1.6\n"
    model, warnings = _read(tmp_path, _mat24(card2=(40.4, 5.0, 0, 9)), rates)
    assert model.material_model.tolist() == [CODES["piecewise_linear"]] and model.rate_curve.tolist() == [0]
    assert _curve(model, 0) == ([0.0, 100.0], [1.0, 1.6])
    assert any("LCSR = 9 and C = 40.4; the rate curve is used" in w for w in warnings)
    with pytest.raises(KeywordError, match=r"C = 40\.4, P = 0: the Cowper-Symonds constants must both be > 0"):
        _read(tmp_path, _mat24(card2=(40.4,)))


def test_fail_is_the_failure_strain_and_mat81_damage_is_named_as_not_modelled(tmp_path: Path) -> None:
    """FAIL is the material's failure_strain (element erosion), its default 1e21 none; a negative
    FAIL (a user subroutine) is refused; MAT 81's damage is not modelled: a warning naming the
    material, and its EPPF is no failure strain."""
    model, warnings = _read(tmp_path, _mat24(card1=(1, 7800.0, 2e11, 0.3, 2.5e8, 1e9, 0.3)))
    assert model.failure_strain.tolist() == [0.3] and not any("FAIL" in w for w in warnings)
    model, warnings = _read(tmp_path, _mat24())
    assert model.failure_strain is None or model.failure_strain.tolist() == [0.0]   # the default (1e21) is none
    with pytest.raises(KeywordError, match=r"FAIL = -1 asks for a user failure subroutine"):
        _read(tmp_path, _mat24(card1=(1, 7800.0, 2e11, 0.3, 2.5e8, 1e9, -1.0)))
    model, warnings = _read(tmp_path, _mat24(card1=(1, 7800.0, 2e11, 0.3, 2.5e8, 1e9, 0.2),
                                             keyword="MAT_PLASTICITY_WITH_DAMAGE"))
    assert model.material_model.tolist() == [CODES["piecewise_linear"]]
    assert model.failure_strain is None or model.failure_strain.tolist() == [0.0]
    assert any("*MAT_PLASTICITY_WITH_DAMAGE 1 is read as *MAT_PIECEWISE_LINEAR_PLASTICITY: its damage (EPPF, "
               "EPPFR, LCDM) is not modelled" in w for w in warnings)


def test_a_curve_past_zero_is_extrapolated_and_a_softening_one_refused(tmp_path: Path) -> None:
    model, warnings = _read(tmp_path, _mat24(eps=(0.01, 0.11), es=(2.6e8, 3.6e8)))
    assert _curve(model, 0) == ([0.0, 0.01, 0.11], [pytest.approx(2.5e8), 2.6e8, 3.6e8])
    assert any("starts at plastic strain 0.01, not 0; it is taken from (0, 2.5e+08 Pa)" in w for w in warnings)
    with pytest.raises(KeywordError, match=r"\*MAT_PIECEWISE_LINEAR_PLASTICITY 1: the stress-strain curve .* the "
                                           r"yield stress decreases to 2e\+08 at plastic strain 0.1"):
        _read(tmp_path, _mat24(eps=(0.0, 0.1), es=(2.6e8, 2e8)))


@pytest.mark.skipif(not REAL_DECK.exists(), reason="the real decks (../shared/realdecks) are not here")
def test_the_ball_plate_deck_mat24_card_is_read() -> None:
    """pydyna's ball-and-plate deck (mm-kg-ms): part 1's *MAT_PIECEWISE_LINEAR_PLASTICITY (RO 7.83e-6,
    E 207, PR 0.3, SIGY 0.2, ETAN 2.0, no curve, no rate) is read as piecewise_linear, bilinear:
    7830 kg/m^3, 207 GPa, 200 MPa, 2 GPa. (The deck's rigid ball, *MAT_RIGID, is not read yet.)"""
    data = collect(read_keyword_file(REAL_DECK))
    assert not any("MAT_PIECEWISE_LINEAR_PLASTICITY" in w for w in data.warnings)
    curves: list[object] = []
    spec = material_of(1, data, Units.named("mm-kg-ms"), curves)
    assert (spec.model, curves, spec.extra) == ("piecewise_linear", [], {"hardening_curve": None, "rate_curve": None})
    assert np.allclose([spec.density, spec.youngs_modulus, spec.poisson_ratio, spec.yield_stress,
                        spec.tangent_modulus], [7830.0, 207e9, 0.3, 2e8, 2e9], rtol=1e-12)
