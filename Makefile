# The two commands of the README: `make demo` (the paper's pipe whip) and `make test`.
# Both install what is missing first; running them again only rebuilds what changed.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.paradyn-installed
SOURCES := pyproject.toml $(shell find fortran frontend -type f -not -name '*.pyc' 2>/dev/null)
# the deck and results schema: the Python tables, the Fortran module and the docs tables follow from it
SCHEMA := $(wildcard schema/*.toml) schema/generate.py $(wildcard schema/*_writer.py) schema/schema_model.py

.PHONY: demo test test-extra test-all install engine bench clean stability

demo: $(STAMP)
	$(VENV)/bin/paradyn-run cases/pipe_whip/scene.toml -o runs/pipe_whip --plots
	$(PY) cases/pipe_whip/compare.py runs/pipe_whip

# make test leaves out the tests that build the engine again (marked build) and the long runs that
# have a quicker variant in it (marked slow); make test-extra runs just those, make test-all
# everything. CI (.ci/run) runs make test, then make test-extra.
test: $(STAMP)
	$(PY) -m pytest -q -m "not build and not slow"

test-extra: $(STAMP)
	$(PY) -m pytest -q -m "build or slow"

test-all: $(STAMP)
	$(PY) -m pytest -q

install: $(STAMP)

$(STAMP): $(SOURCES) $(SCHEMA) setup/system-packages.sh
	bash setup/system-packages.sh
	$(PYTHON) schema/generate.py
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q "scikit-build-core>=0.10" "numpy>=1.26"
	$(PY) -m pip install -q --no-build-isolation ".[test]"
	touch $@

# The stability suite (docs/stability.md, generated): hard cases judged by energy balance, hourglass
# energy, penetration and momentum; writes docs/stability.md
stability: $(STAMP)
	$(PY) tests/stability/stability_suite.py

# Kernel speed: microseconds per element-cycle, elastic and plastic (docs/performance.md)
bench: $(STAMP)
	$(PY) -c "from paradyn.running.launch import engine_path; import subprocess; subprocess.run([str(engine_path().with_name('paradyn-kernel-benchmark'))], check=True)"

# The engine alone, for cluster users: build/engine/paradyn-engine
engine:
	cmake -S fortran -B build/engine && cmake --build build/engine -j

clean:
	rm -rf build $(VENV) runs
