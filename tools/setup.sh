#!/usr/bin/env bash
# One-time set-up of a fresh machine: libLLVM 19 for Dr.Jit's LLVM back-end
# (Debian's LLVM 14/15 crash), then csuas with its test extras, editable.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! ls /usr/lib/*/libLLVM-19.so* >/dev/null 2>&1 && ! ls /usr/lib/libLLVM-19.so* >/dev/null 2>&1; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "setup: installing libllvm19 for Dr.Jit" >&2
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19 >/dev/null
  else
    echo "setup: libLLVM 19 not found; install it (apt-get install libllvm19) or set DRJIT_LIBLLVM_PATH" >&2
  fi
fi
python3 -m pip install -q --disable-pip-version-check -e ".[test]" 2>&1 | grep -v -E "^WARNING: (Location|Running pip)" || true
python3 -c "import csuas, mitsuba, drjit, sionna.rt, trimesh" || { echo "setup: import check failed" >&2; exit 1; }
