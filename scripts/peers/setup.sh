#!/usr/bin/env bash
# scripts/peers/setup.sh — install the optional peer renderers of scripts/peers/time_to_error.py.
#
# usage: scripts/peers/setup.sh [--no-apt] [--no-pip]
#
#   apt (Debian 12): blender (Cycles 3.4.1) and libllvm19 (Mitsuba's llvm_ad_rgb variant
#                    needs libLLVM >= 16; Debian's default LLVM 15 makes Dr.Jit abort)
#   pip:             mitsuba==3.9.1 and numpy into build/peers/venv, unless $WP_MITSUBA_PYTHON
#                    already names a Python that imports mitsuba
#
# Nothing in the build, the tests or CI needs these; time_to_error.py skips what is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."

apt=1 pip=1
for a in "$@"; do
    case "$a" in
        --no-apt) apt=0 ;;
        --no-pip) pip=0 ;;
        -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
        *) echo "setup.sh: unknown option $a" >&2; exit 2 ;;
    esac
done

if [[ $apt == 1 ]]; then
    if command -v apt-get >/dev/null; then
        sudo=""
        [[ $(id -u) != 0 ]] && sudo="sudo"
        $sudo apt-get update
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends blender libllvm19
    else
        echo "setup.sh: no apt-get: install Blender (Cycles) and libLLVM >= 16 yourself" >&2
    fi
fi

if [[ $pip == 1 ]]; then
    if [[ -n "${WP_MITSUBA_PYTHON:-}" ]] && "$WP_MITSUBA_PYTHON" -c "import mitsuba, numpy" 2>/dev/null; then
        echo "setup.sh: using $WP_MITSUBA_PYTHON (imports mitsuba $("$WP_MITSUBA_PYTHON" -c 'import mitsuba; print(mitsuba.__version__)'))"
    else
        python3 -m venv build/peers/venv
        build/peers/venv/bin/pip install --upgrade pip
        build/peers/venv/bin/pip install "mitsuba==3.9.1" numpy
        echo "setup.sh: Mitsuba in build/peers/venv (time_to_error.py finds it there)"
    fi
fi

echo "setup.sh: done; run: python3 scripts/peers/time_to_error.py --help"
