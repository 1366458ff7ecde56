#!/usr/bin/env bash
# Imports a GLB into Blender (in the background, no window) and prints its
# shape keys and the animation's frame range:
#
#   tools/blender/import_glb.sh FILE.glb
#
# Needs Debian's `blender` (apt-get install blender). Blender 3.4's glTF
# importer uses `np.bool`, which numpy 1.24 removed: a numpy 1.23.5 wheel for
# Blender's Python (3.11) is fetched once with pip into tools/blender/.numpy
# (or $MESHMORPH_BLENDER_NUMPY) and put first on Blender's sys.path.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if [ $# -ne 1 ]; then
    echo "usage: $0 FILE.glb" >&2
    exit 2
fi
glb="$(realpath "$1")"
blender="${BLENDER:-blender}"
command -v "$blender" >/dev/null || { echo "blender not found (apt-get install blender)" >&2; exit 2; }
numpy_dir="${MESHMORPH_BLENDER_NUMPY:-$here/.numpy}"
if [ ! -d "$numpy_dir/numpy" ]; then
    wheels="$(mktemp -d)"
    trap 'rm -rf "$wheels"' EXIT
    python3 -m pip download --quiet numpy==1.23.5 --no-deps --python-version 3.11 \
        --only-binary=:all: -d "$wheels" >&2
    mkdir -p "$numpy_dir"
    python3 -m zipfile -e "$wheels"/numpy-1.23.5-*.whl "$numpy_dir"
fi
MESHMORPH_BLENDER_NUMPY="$numpy_dir" "$blender" --background --factory-startup \
    --python "$here/import_glb.py" -- "$glb" 2>&1 | sed -n '/^meshmorph-import/,$p'
exit "${PIPESTATUS[0]}"
