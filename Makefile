# pygear: `make run` runs the default case, `make test` the test suite; both set up
# what they need first on a fresh machine (scripts/setup.sh), and no more: `make run`
# installs the runtime alone, `make test` and `make lint` add the test extra and the CF
# checkers, `make docs` the docs extra. A stamp per level in the venv keeps each level
# to one set-up; editing pyproject.toml, meson.build or scripts/setup.sh redoes them.
VENV ?= .venv
PY := $(VENV)/bin/python
RUNTIME := $(VENV)/.pygear-runtime
TESTING := $(VENV)/.pygear-test
DOCS := $(VENV)/.pygear-docs
CASE ?= yang2016_planetary

.PHONY: setup run test test-slow lint bench docs clean

$(RUNTIME): pyproject.toml meson.build scripts/setup.sh
	VENV=$(VENV) bash scripts/setup.sh runtime
	touch $@

$(TESTING): $(RUNTIME)
	VENV=$(VENV) bash scripts/setup.sh test
	touch $@

$(DOCS): $(RUNTIME)
	VENV=$(VENV) bash scripts/setup.sh docs
	touch $@

# everything a developer (or CI) uses: the runtime, the test and the docs extras
setup: $(RUNTIME) $(TESTING) $(DOCS)

run: $(RUNTIME)
	$(VENV)/bin/pygear run $(CASE) --out out/$(CASE)

test: $(TESTING)
	$(PY) -m pytest

# long runs; pytest exits 5 when none is marked slow yet
test-slow: $(TESTING)
	$(PY) -m pytest -m slow || [ $$? -eq 5 ]

lint: $(TESTING)
	$(VENV)/bin/ruff check pygear tests benchmarks cases docs

bench: $(RUNTIME)
	for script in benchmarks/bench_*.py; do $(PY) $$script || exit 1; done
	$(PY) benchmarks/bench_newmark.py --case gearbox

# the documentation site: docs/_build/html/index.html; warnings are errors, and the
# tutorial notebooks run during the build
docs: $(DOCS)
	$(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf build out .pytest_cache docs/_build docs/generated
