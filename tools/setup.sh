#!/usr/bin/env bash
# Set-up of a fresh machine, run by `make report` and `make test`:
#   1. Debian packages: libLLVM 19 for Dr.Jit's LLVM back-end (Debian's LLVM 14/15 crash it) and
#      gdal-bin (GDAL's gdal_viewshed, the independent reference of the line-of-sight checks);
#   2. a virtual environment of csuas's own (CSUAS_VENV, default .venv), created when missing,
#      because Debian's system Python refuses `pip install` (PEP 668);
#   3. csuas with its test extras, editable, into that environment; skipped when pyproject.toml
#      has not changed since the last successful install (a stamp file inside the environment).
# Every step says what it does; the pip step prints one line per package it installs.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CSUAS_VENV:-.venv}"
say() { printf 'setup: %s\n' "$*" >&2; }
started=$(date +%s)

# Debian packages: libLLVM 19 for Dr.Jit, GDAL's programs for the viewshed cross-check (tests, report)
missing=()
if ! ls /usr/lib/*/libLLVM-19.so* >/dev/null 2>&1 && ! ls /usr/lib/libLLVM-19.so* >/dev/null 2>&1; then
  missing+=(libllvm19)
fi
command -v gdal_viewshed >/dev/null 2>&1 || missing+=(gdal-bin)
if [ ${#missing[@]} -gt 0 ]; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    say "installing Debian's ${missing[*]} (about 30 s)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    say "missing Debian packages ${missing[*]}: install them (apt-get install ${missing[*]}); without libllvm19"
    say "set DRJIT_LIBLLVM_PATH to a libLLVM 19; without gdal-bin the GDAL viewshed cross-checks are skipped"
  fi
fi

if [ ! -x "$venv/bin/python" ]; then
  say "creating the virtual environment $venv"
  python3 -m venv "$venv" || { say "python3 -m venv failed: install python3-venv (apt-get install python3-venv)"; exit 1; }
fi

stamp="$venv/.csuas-installed"
want=$(cat pyproject.toml tools/setup.sh | sha256sum | cut -c1-16)
if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  say "installing csuas and its dependencies into $venv (about 3 min with an empty pip cache)"
  log=$(mktemp)
  { "$venv/bin/python" -m pip install --disable-pip-version-check --progress-bar off -e ".[test]" 2>&1
    echo "pip-exit-status $?"; } | tee "$log" \
    | grep --line-buffered -E "^(Collecting|Successfully|ERROR)" | sed -u 's/^/setup:   /' >&2 || true
  rc=$(sed -n 's/^pip-exit-status //p' "$log")
  if [ "$rc" != 0 ]; then
    tail -n 30 "$log" | grep -v '^pip-exit-status' | sed 's/^/setup:   /' >&2
    rm -f "$log"; say "pip install failed (exit $rc): the lines above say why"; exit 1
  fi
  rm -f "$log"
  "$venv/bin/python" -c "import csuas, mitsuba, drjit, sionna.rt, trimesh, mapbox_earcut" \
    || { say "import check failed: the install above did not complete"; exit 1; }
  echo "$want" > "$stamp"
else
  say "$venv is up to date with pyproject.toml"
fi
say "done in $(( $(date +%s) - started )) s"
