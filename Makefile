# pygear: `make run` runs the default case, `make test` the test suite; both set
# everything up first on a fresh machine (scripts/setup.sh).
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.pygear-installed
CASE ?= yang2016_planetary

.PHONY: setup run test test-slow lint bench docs clean

$(STAMP): pyproject.toml meson.build scripts/setup.sh
	VENV=$(VENV) bash scripts/setup.sh
	touch $@

setup: $(STAMP)

run: $(STAMP)
	$(VENV)/bin/pygear run $(CASE) --out out/$(CASE)

test: $(STAMP)
	$(PY) -m pytest

# long runs; pytest exits 5 when none is marked slow yet
test-slow: $(STAMP)
	$(PY) -m pytest -m slow || [ $$? -eq 5 ]

lint: $(STAMP)
	$(VENV)/bin/ruff check pygear tests benchmarks cases docs

bench: $(STAMP)
	for script in benchmarks/bench_*.py; do $(PY) $$script || exit 1; done
	$(PY) benchmarks/bench_newmark.py --case gearbox

# the documentation site: docs/_build/html/index.html; warnings are errors, and the
# tutorial notebooks run during the build
docs: $(STAMP)
	$(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf build out .pytest_cache docs/_build docs/generated
