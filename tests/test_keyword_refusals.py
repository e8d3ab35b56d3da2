"""What a keyword deck that cannot run as written is told (issue 33, item 7): an implicit deck is
refused, naming the keywords to drop; an error carries the warnings collected before it (a skipped
keyword is often the cause); a model in which nothing moves or is loaded gets a warning before the
run. Each deck is a small plate written out in the test (tests/test_keyword.py's)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import load_keyword
from paradyn.running import preflight
from test_keyword import HEAD, MESH

REALDECKS = Path(__file__).resolve().parents[1].parent / "shared" / "realdecks"
IMPLICIT = """*CONTROL_IMPLICIT_GENERAL
         1      0.01
*CONTROL_IMPLICIT_SOLUTION
         2
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "model.k"
    path.write_text(text + "*END\n")
    return path


def test_an_implicit_deck_is_refused_naming_what_to_drop(tmp_path: Path) -> None:
    with pytest.raises(KeywordError) as refused:
        load_keyword(_write(tmp_path, HEAD + IMPLICIT + MESH))
    message = str(refused.value)
    assert "IMFLAG = 1 asks for an implicit analysis; ParaDyn is explicit" in message
    assert "*CONTROL_IMPLICIT_GENERAL (" in message and "*CONTROL_IMPLICIT_SOLUTION (" in message
    assert "or set IMFLAG = 0" in message


def test_imflag_zero_is_explicit_and_reads(tmp_path: Path) -> None:
    model = load_keyword(_write(tmp_path, HEAD + IMPLICIT.replace("         1      0.01", "         0      0.01")
                                + MESH)).model
    assert model.n_elements == 2


@pytest.mark.skipif(not (REALDECKS / "pydyna_beer_can").is_dir(), reason="../shared/realdecks is not beside the clone")
def test_the_beer_can_deck_is_refused_as_implicit() -> None:
    """The public beer-can deck (../shared/realdecks/pydyna_beer_can, written for LS-DYNA's implicit
    solver) is refused, naming its four *CONTROL_IMPLICIT_* keywords."""
    with pytest.raises(KeywordError) as refused:
        load_keyword(REALDECKS / "pydyna_beer_can" / "beer_can.k")
    message = str(refused.value)
    assert "ParaDyn is explicit" in message
    for name in ("AUTO", "DYNAMICS", "GENERAL", "SOLUTION"):
        assert f"*CONTROL_IMPLICIT_{name} (" in message


def test_an_error_carries_the_warnings_before_it(tmp_path: Path) -> None:
    """A material the reader skips (with a warning) leaves its part without a material: the error
    about the part comes with the warning that says why."""
    head = HEAD.replace("*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n",
                        "*MAT_JOHNSON_COOK\n         1    7800.0     8e+10     2e+11       0.3\n")
    with pytest.raises(KeywordError) as refused:
        load_keyword(_write(tmp_path, head + MESH))
    message = str(refused.value)
    assert "names material 1" in message
    assert "warnings before this error" in message
    assert "*MAT_JOHNSON_COOK is not supported by ParaDyn and is ignored" in message


def test_a_model_where_nothing_acts_is_warned_before_the_run(tmp_path: Path) -> None:
    model = load_keyword(_write(tmp_path, HEAD + MESH)).model
    warnings = preflight.check_model(model).warnings
    assert any(w.startswith("nothing in this model moves or is loaded") for w in warnings)
    model.initial_velocity = np.full_like(model.coordinates, 0.0)
    model.initial_velocity[0, 2] = 1.0
    assert not any("nothing in this model" in w for w in preflight.check_model(model).warnings)
