#!/usr/bin/env bash
# The README's install, offline: a virtual environment that sees Debian's NumPy, the package
# installed into it by pip without an index, then imported from outside the repository and a
# small solve run. Usage: install.sh PYTHON BUILD_DIR (CTest: python.install).
set -euo pipefail
python="$1"
build="$(cd "$2" && pwd)"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# Files in python/ that git ignores (setuptools' build/ and *.egg-info would be such).
ignored() {
  (cd "$repo" && git status --porcelain --ignored python 2>/dev/null | grep '^!!' |
     grep -v __pycache__ || true)
}
before="$(ignored)"
# As README.md and docs/python.md say, with the build folder named.
"$python" -m venv --system-site-packages --without-pip "$work/venv"
(cd "$repo" && CMCSURF_BUILD_DIR="$build" PIP_NO_INPUT=1 \
   "$work/venv/bin/python" -m pip install -q --no-build-isolation --no-index ./python) \
  || fail "pip install --no-build-isolation --no-index ./python"
[ "$(ignored)" = "$before" ] || fail "the install left files in python/: $(ignored)"

cd "$work"  # not the repository, not the build tree: the installed package must be the one
OMP_NUM_THREADS=1 PYTHONPATH= "$work/venv/bin/python" - "$work/venv" <<'PY'
import pathlib, sys
import cmcsurf
venv = pathlib.Path(sys.argv[1]).resolve()
where = pathlib.Path(cmcsurf.__file__).resolve()
assert venv in where.parents, f"imported {where}, not the installed package under {venv}"
assert (where.parent / "py.typed").exists() and (where.parent / "_cmcsurf.pyi").exists()
r = cmcsurf.run("G", 0.5, 16, epsilon=0.05, threads=1)
# The gyroid's area at alpha = 1/2 is 3.09 per unit cell (Schoen); 16^3 at epsilon 0.05 is
# coarse, so within 3 %.
assert abs(r.report["area"] - 3.09) < 0.03 * 3.09, r.report["area"]
assert r.phi.shape == (16, 16, 16)
m = cmcsurf.mesh(r, solid="network")
assert m.report["checks"]["closed"] and len(m.faces) > 100
print(f"install: cmcsurf {cmcsurf.__version__} from {where.parent}: area {r.report['area']:.4f}")
PY
echo "install: all passed"
