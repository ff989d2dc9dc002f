#!/bin/sh
# Print the Python interpreter to build .venv with: $PYTHON where it is set, else python3.11
# (pybullet publishes wheels for it), else the newest supported one (pybullet is then built
# from source: a note says so on stderr). With none usable, say what to install and exit 1.
usable() {
    # A supported version, with venv and ensurepip (Debian ships them apart: pythonX.Y-venv).
    "$1" -c 'import sys, venv, ensurepip; sys.exit(not (3, 11) <= sys.version_info[:2] <= (3, 13))' \
        >/dev/null 2>&1
}
if [ -n "${PYTHON:-}" ]; then
    candidates="$PYTHON"
else
    candidates="python3.11 python3.13 python3.12 python3"
fi
for python in $candidates; do
    if command -v "$python" >/dev/null 2>&1 && usable "$python"; then
        version=$("$python" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
        if [ "$version" != "3.11" ]; then
            echo "note: pybullet has no wheel for Python $version: pip builds it from source," \
                "which needs a C++ compiler (g++) and takes several minutes" >&2
        fi
        echo "$python"
        exit 0
    fi
done
echo "qdsega needs Python 3.11 with venv (e.g. apt install python3.11-venv, brew install" \
    "python@3.11), or 3.12-3.13 and a C++ compiler; found none usable among: $candidates" >&2
exit 1
