#!/usr/bin/env bash
# Set up pygear on a fresh machine: system packages (a Fortran compiler, LAPACK,
# pkg-config), a virtual environment, and the package built by meson-python.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}

missing=()
command -v gfortran >/dev/null || missing+=(gfortran)
command -v pkg-config >/dev/null || missing+=(pkg-config)
pkg-config --exists lapack 2>/dev/null || pkg-config --exists openblas 2>/dev/null \
  || missing+=(libopenblas-dev)
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing ${missing[*]} with apt-get" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq gfortran libopenblas-dev pkg-config
  else
    echo "setup: please install ${missing[*]} (Debian: gfortran libopenblas-dev pkg-config)" >&2
    exit 1
  fi
fi

[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q "numpy>=1.26" "meson-python>=0.15" "meson>=1.1" ninja
# editable: the extension is rebuilt on import whenever a Fortran or Python file changed
"$VENV/bin/python" -m pip install -q --no-build-isolation -e ".[test]"
"$VENV/bin/python" -c "import pygear._kernel" && echo "setup: pygear is installed in $VENV" >&2
