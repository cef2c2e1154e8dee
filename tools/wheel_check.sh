#!/bin/bash
# make wheel-check: the wheel on a Debian 12 that has never seen a compiler. A minimal root
# (debootstrap --variant=minbase, then python3, python3-venv and the four system libraries of the
# manylinux policy the wheel uses: no gcc, no -dev package, none of vwg's libraries) is made once in
# build/debian12-root; the wheel is pip-installed into a venv there,
# `vwg run office --goal kitchen --record` runs inside it (chroot), and its frames are compared with
# the same run of the source build here.
set -euo pipefail
ROOT_DIR=${ROOT_DIR:-build/debian12-root}
WHEEL=$(ls dist/vwg-*-cp311-cp311-manylinux_*.whl | tail -n 1)
MIRROR=${MIRROR:-http://deb.debian.org/debian}
start=$(date +%s)
if [ ! -x "$ROOT_DIR/usr/bin/python3" ]; then
  echo "wheel-check: a minimal Debian 12 root in $ROOT_DIR (debootstrap, first time a few minutes)"
  rm -rf "$ROOT_DIR"
  debootstrap --variant=minbase bookworm "$ROOT_DIR" "$MIRROR" > build/debootstrap.log 2>&1 \
    || { tail -20 build/debootstrap.log; exit 1; }
  cp /etc/resolv.conf "$ROOT_DIR/etc/resolv.conf"
  chroot "$ROOT_DIR" apt-get install -y -q --no-install-recommends python3 python3-venv > build/debootstrap-py.log 2>&1 \
    || { tail -20 build/debootstrap-py.log; exit 1; }
fi
cp /etc/resolv.conf "$ROOT_DIR/etc/resolv.conf"
# This machine's trusted certificates (a proxy's CA, if it has one), for pip in the root to reach PyPI.
if [ -f /etc/ssl/certs/ca-certificates.crt ]; then
  mkdir -p "$ROOT_DIR/etc/ssl/certs" && cp /etc/ssl/certs/ca-certificates.crt "$ROOT_DIR/etc/ssl/certs/"
fi
# The manylinux policy lets a wheel take a few libraries from the system (auditwheel's list: GLib, the X11
# client libraries, zlib, expat, ...) rather than bundle them; a desktop or a server with GLib has them, a
# minbase root does not. Those the wheel needs (through OpenCV's image modules) are installed here, and
# nothing else: no compiler, no -dev package, none of vwg's libraries.
SYSTEM_LIBS="libglib2.0-0 libx11-6 libxext6 libxrender1"
env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root chroot "$ROOT_DIR" \
  apt-get install -y -q --no-install-recommends $SYSTEM_LIBS > build/debootstrap-libs.log 2>&1 \
  || { tail -20 build/debootstrap-libs.log; exit 1; }
# No compiler in there: the wheel must not need one.
if chroot "$ROOT_DIR" sh -c 'command -v gcc || command -v cc || command -v c++' > /dev/null; then
  echo "wheel-check: $ROOT_DIR has a compiler; it must not"; exit 1
fi
rm -rf "$ROOT_DIR/check" && mkdir -p "$ROOT_DIR/check/run"
cp "$WHEEL" "$ROOT_DIR/check/"
mount -t proc proc "$ROOT_DIR/proc" 2>/dev/null || true
trap 'umount "$ROOT_DIR/proc" 2>/dev/null || true' EXIT
env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root PIP_CERT=/etc/ssl/certs/ca-certificates.crt \
  chroot "$ROOT_DIR" sh -c "python3 -m venv /check/venv && /check/venv/bin/pip install -q /check/$(basename "$WHEEL")" \
  > build/wheel-check-pip.log 2>&1 || { tail -20 build/wheel-check-pip.log; exit 1; }
env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root \
  chroot "$ROOT_DIR" sh -c "cd /check/run && /check/venv/bin/vwg run office --goal kitchen --record wheel.jsonl --threads 2"
# The same run from the source build, and the frames compared (events, strings, blobs; not the chain's links,
# which follow the headers' world file paths).
rm -rf build/wheel-check && mkdir -p build/wheel-check
(cd build/wheel-check && PYTHONPATH=$OLDPWD/python $OLDPWD/.venv/bin/python -m vwg.cli run office --goal kitchen \
  --record source.jsonl --quiet)
PYTHONPATH=python .venv/bin/python - "$ROOT_DIR/check/run/wheel.jsonl" build/wheel-check/source.jsonl <<'PY'
import json, sys
from vwg.io.record import read_record
a, b = (read_record(p).frames for p in sys.argv[1:3])
line = lambda f: json.dumps({k: v for k, v in f.items() if k != "prev"}, sort_keys=True)
assert len(a) == len(b) and all(line(x) == line(y) for x, y in zip(a, b)), "the wheel's frames differ from the source build's"
print(f"wheel-check: {len(a)} frames, the same as the source build's")
PY
echo "wheel-check: ok in $(( $(date +%s) - start )) s ($(basename "$WHEEL"), $(du -h "$WHEEL" | cut -f1))"
