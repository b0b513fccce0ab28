# pygear: `make run` runs the default case, `make test` the test suite; both set
# everything up first on a fresh machine (scripts/setup.sh).
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.pygear-installed
CASE ?= yang2016_planetary

.PHONY: setup run test test-slow lint bench clean

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
	$(VENV)/bin/ruff check pygear tests benchmarks cases

bench: $(STAMP)
	for script in benchmarks/bench_*.py; do $(PY) $$script || exit 1; done
	$(PY) benchmarks/bench_newmark.py --case gearbox

clean:
	rm -rf build out .pytest_cache
