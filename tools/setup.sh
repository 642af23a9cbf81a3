#!/usr/bin/env bash
# Set-up of a fresh machine, run by `make report` and `make test`:
#   1. Debian packages: libLLVM 19 for Dr.Jit's LLVM back-end (Debian's LLVM 14/15 crash it),
#      gdal-bin (GDAL's gdal_viewshed, the independent reference of the line-of-sight checks) and
#      chromium (the report's browser test opens report.html in it); when another process holds
#      apt's locks (an upgrade, another install), set-up waits for them up to 10 min and says so;
#   2. a virtual environment of csuas's own (CSUAS_VENV, default .venv), created when missing,
#      because Debian's system Python refuses `pip install` (PEP 668);
#   3. csuas with its test extras, editable, into that environment; skipped when pyproject.toml
#      has not changed since the last successful install (a stamp file inside the environment).
# Every step says what it does and is never silent for more than 10 s: the pip step prints one line
# per package it collects, and a long step (apt waiting for its lock, pip building and installing)
# prints how long it has run and its last line of output every 10 s.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CSUAS_VENV:-.venv}"
say() { printf 'setup: %s\n' "$*" >&2; }
started=$(date +%s)

#: Silence after which a step prints its elapsed time and last line of output [s]; checked every
#: second, so that set-up is never silent for more than 10 s.
quiet_s=9
#: How long set-up waits for apt's locks held by another process [s].
apt_lock_wait_s=600

# watched WHAT LOG SHOW_RE COMMAND...: run COMMAND with its output in LOG; print its lines that match
# SHOW_RE as they come and, after quiet_s seconds without a printed line, WHAT, the time so far and
# COMMAND's last line. Returns COMMAND's exit status; Ctrl-C or SIGTERM stop COMMAND too.
watched() {
  local what=$1 log=$2 show=$3 pid running seen=0 n new last shown_last='' rc started_at=$SECONDS quiet_since=$SECONDS
  shift 3
  "$@" >"$log" 2>&1 &
  pid=$!
  trap 'kill "$pid" 2>/dev/null; exit 130' INT
  trap 'kill "$pid" 2>/dev/null; exit 143' TERM
  while :; do
    kill -0 "$pid" 2>/dev/null && running=1 || running=0
    n=$(tr '\r' '\n' <"$log" | wc -l)
    if [ "$n" -gt "$seen" ]; then
      new=$(tr '\r' '\n' <"$log" | sed -n "$((seen + 1)),${n}p" | grep -E "$show" || true)
      seen=$n
      if [ -n "$new" ]; then printf '%s\n' "$new" | sed 's/^/setup:   /' >&2; quiet_since=$SECONDS; fi
    fi
    [ "$running" = 1 ] || break
    if [ $((SECONDS - quiet_since)) -ge "$quiet_s" ]; then
      last=$(tr '\r' '\n' <"$log" | grep -v '^[[:space:]]*$' | tail -n 1 | cut -c1-110 || true)
      if [ -n "$last" ] && [ "$last" = "$shown_last" ]; then
        say "  $what: $((SECONDS - started_at)) s so far (same step)"
      else
        say "  $what: $((SECONDS - started_at)) s so far${last:+ (now: $last)}"
      fi
      shown_last=$last
      quiet_since=$SECONDS
    fi
    sleep 1
  done
  rc=0
  wait "$pid" || rc=$?
  trap - INT TERM
  return "$rc"
}

# apt_get ARGS...: apt-get that waits for apt's locks: the dpkg lock through apt's own timeout
# (it prints "Waiting for cache lock", shown every 10 s), the package lists' lock of `apt-get update`
# (which apt's timeout does not cover) by retrying every 5 s; both for at most apt_lock_wait_s.
apt_get() {
  local log deadline=$((SECONDS + apt_lock_wait_s)) rc
  log=$(mktemp)
  while :; do
    rc=0
    watched "apt-get $1" "$log" '^E:' env DEBIAN_FRONTEND=noninteractive \
      apt-get -q -o DPkg::Lock::Timeout="$apt_lock_wait_s" "$@" || rc=$?
    [ "$rc" != 0 ] || { rm -f "$log"; return 0; }
    if grep -q 'Could not get lock' "$log" && [ "$SECONDS" -lt "$deadline" ]; then
      say "  waiting for apt's lock: $(grep -m1 'Could not get lock' "$log" | cut -c1-150)"
      sleep 5
      continue
    fi
    rm -f "$log"
    return "$rc"
  done
}

# Debian packages: libLLVM 19 for Dr.Jit, GDAL's programs for the viewshed cross-check (tests, report),
# Chromium for the report's browser test
missing=()
if ! ls /usr/lib/*/libLLVM-19.so* >/dev/null 2>&1 && ! ls /usr/lib/libLLVM-19.so* >/dev/null 2>&1; then
  missing+=(libllvm19)
fi
command -v gdal_viewshed >/dev/null 2>&1 || missing+=(gdal-bin)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
if [ ${#missing[@]} -gt 0 ]; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    say "installing Debian's ${missing[*]} (about 1 min with chromium)"
    apt_get update && apt_get install -y --no-install-recommends "${missing[@]}" \
      || { say "apt-get failed: the lines above say why"; exit 1; }
  else
    say "missing Debian packages ${missing[*]}: install them (apt-get install ${missing[*]}); without libllvm19"
    say "set DRJIT_LIBLLVM_PATH to a libLLVM 19; without gdal-bin the GDAL viewshed cross-checks are skipped,"
    say "without chromium the report's browser test"
  fi
fi

if [ ! -x "$venv/bin/python" ]; then
  say "creating the virtual environment $venv"
  log=$(mktemp)
  watched "python3 -m venv" "$log" '^Error' python3 -m venv "$venv" \
    || { rm -f "$log"; say "python3 -m venv failed: install python3-venv (apt-get install python3-venv)"; exit 1; }
  rm -f "$log"
fi

stamp="$venv/.csuas-installed"
want=$(cat pyproject.toml tools/setup.sh | sha256sum | cut -c1-16)
if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  say "installing csuas and its dependencies into $venv (about 3 min with an empty pip cache)"
  log=$(mktemp)
  rc=0
  watched "pip install" "$log" "^(Collecting|Successfully|ERROR)" \
    "$venv/bin/python" -m pip install --disable-pip-version-check --progress-bar off -e ".[test]" || rc=$?
  if [ "$rc" != 0 ]; then
    tail -n 30 "$log" | sed 's/^/setup:   /' >&2
    rm -f "$log"; say "pip install failed (exit $rc): the lines above say why"; exit 1
  fi
  say "checking that csuas and its simulators import"
  watched "import check" "$log" "Error" "$venv/bin/python" -c "import csuas, mitsuba, drjit, sionna.rt, trimesh, mapbox_earcut" \
    || { rm -f "$log"; say "import check failed: the install above did not complete"; exit 1; }
  rm -f "$log"
  echo "$want" > "$stamp"
else
  say "$venv is up to date with pyproject.toml"
fi
say "done in $(( $(date +%s) - started )) s"
