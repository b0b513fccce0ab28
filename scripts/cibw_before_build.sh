#!/usr/bin/env bash
# cibuildwheel, before each wheel is built: the scipy-openblas32 wheel in the build
# environment and its pkg-config file in PROJECT/.openblas/, where meson looks
# (pyproject.toml: -Dpkg_config_path).  auditwheel then finds the library through
# LD_LIBRARY_PATH and copies it into the wheel.
set -euo pipefail
project=${1:-$PWD}
python -m pip install "scipy-openblas32>=0.3.30"
mkdir -p "$project/.openblas"
python -c "import scipy_openblas32 as s; print(s.get_pkg_config())" \
  > "$project/.openblas/scipy-openblas.pc"
cat "$project/.openblas/scipy-openblas.pc"
