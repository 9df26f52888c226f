#!/usr/bin/env bash
# Idempotent set-up of a Debian 12 (bookworm) machine for wrsim: ngspice >= 46, GHDL, and the Python
# venv ./.venv with wrsim installed editable. Run as root (or as a user with sudo); a second run only
# checks. Prints one line per step; exits non-zero with a message when something cannot be installed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export DEBIAN_FRONTEND=noninteractive

NGSPICE_MIN=46  # = MIN_NGSPICE in tools/wrsim/backend/ngspice/batch.py
BACKPORTS_LIST=/etc/apt/sources.list.d/bookworm-backports.sources
VENV=.venv
STAMP=$VENV/.wrsim-pyproject.sha256

die() { echo "setup: error: $*" >&2; exit 1; }

ROOT_CMD=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 && ROOT_CMD=(sudo) || ROOT_CMD=(false)
fi
need_root() { [ "${ROOT_CMD[*]}" != false ] || die "must install packages but am neither root nor able to use sudo"; }
as_root() { "${ROOT_CMD[@]}" env DEBIAN_FRONTEND=noninteractive "$@"; }

# Runs "$@", showing its output only if it fails.
quietly() {
  local log rc=0
  log=$(mktemp)
  "$@" >"$log" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || tail -n 30 "$log" >&2
  rm -f "$log"
  return "$rc"
}

require_bookworm() {
  local codename
  codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
  [ "$codename" = bookworm ] || die "this script installs packages for Debian 12 (bookworm), not '${codename:-unknown}'; install $1 by hand"
}

APT_UPDATED=0
apt_update() {
  if [ "$APT_UPDATED" -eq 0 ]; then
    need_root
    quietly as_root apt-get update || die "apt-get update failed"
    APT_UPDATED=1
  fi
}

apt_install() {
  apt_update
  quietly as_root apt-get install -y --no-install-recommends "$@"
}

ngspice_version() {
  local out
  out=$(ngspice --version </dev/null 2>&1 || true)
  [[ $out =~ ngspice-([0-9]+) ]] && echo "${BASH_REMATCH[1]}"
}

# --- ngspice >= $NGSPICE_MIN (bookworm has 39; bookworm-backports has 46) ---
ver=$(command -v ngspice >/dev/null 2>&1 && ngspice_version || true)
if [ -z "$ver" ] || [ "$ver" -lt "$NGSPICE_MIN" ]; then
  echo "ngspice ${ver:-missing}: installing ngspice >= $NGSPICE_MIN from bookworm-backports"
  require_bookworm "ngspice >= $NGSPICE_MIN"
  need_root
  if ! grep -Eqs '^[^#]*bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/*.list \
    /etc/apt/sources.list.d/*.sources; then
    printf '%s\n' 'Types: deb' 'URIs: http://deb.debian.org/debian' 'Suites: bookworm-backports' \
      'Components: main' 'Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg' |
      as_root tee "$BACKPORTS_LIST" >/dev/null
    echo "added $BACKPORTS_LIST"
  fi
  apt_install -t bookworm-backports ngspice ||
    die "ngspice >= $NGSPICE_MIN not available: add bookworm-backports ($BACKPORTS_LIST) and run 'apt-get install -t bookworm-backports ngspice'"
  ver=$(ngspice_version || true)
  [ -n "$ver" ] && [ "$ver" -ge "$NGSPICE_MIN" ] ||
    die "ngspice >= $NGSPICE_MIN not available: found '${ver:-none}' after installing from bookworm-backports"
fi
echo "ngspice $ver ok"

# --- libngspice and its header, of ngspice's own version: the crossing driver (tools/cosim/wrsim_ngspice.c,
# exact 'above crossings) is compiled against them ---
ngspice_pkg=$(dpkg-query -W -f='${Version}' ngspice 2>/dev/null || true)
for pkg in libngspice0 libngspice0-dev; do
  have=$(dpkg-query -W -f='${Version}' "$pkg" 2>/dev/null || true)
  if [ -n "$ngspice_pkg" ] && [ "$have" != "$ngspice_pkg" ]; then
    echo "$pkg ${have:-missing}: installing $pkg=$ngspice_pkg (the version of ngspice)"
    need_root
    apt_install "$pkg=$ngspice_pkg" || die "cannot install $pkg=$ngspice_pkg with apt-get"
  fi
done
[ -f /usr/include/ngspice/sharedspice.h ] ||
  die "/usr/include/ngspice/sharedspice.h not found: install libngspice0-dev (the version of ngspice $ver)"
echo "libngspice ${ngspice_pkg:-?} ok"

# --- GHDL (bookworm: 2.0); ghdl-llvm too, for 'ghdl-llvm -e -shared' ---
if ! command -v ghdl >/dev/null 2>&1; then
  echo "ghdl missing: installing"
  require_bookworm ghdl
  apt_install ghdl || die "cannot install ghdl with apt-get"
fi
if [ "$(dpkg-query -W -f='${Status}' ghdl-llvm 2>/dev/null || true)" != 'install ok installed' ]; then
  # Package lists never fetched (fresh image): fetch them before deciding ghdl-llvm does not exist.
  compgen -G '/var/lib/apt/lists/*_Packages' >/dev/null || apt_update
  if [[ $(apt-cache policy ghdl-llvm 2>/dev/null) =~ Candidate:\ [0-9] ]]; then
    echo "ghdl-llvm missing: installing"
    apt_install ghdl-llvm || die "cannot install ghdl-llvm with apt-get"
  else
    die "package ghdl-llvm is not available here: digital units (wrsim.ghdl, 'ghdl-llvm -e -shared') need GHDL with the LLVM back-end; install it by hand"
  fi
fi
ghdl_out=$(ghdl --version </dev/null 2>&1) || die "ghdl is installed but 'ghdl --version' fails: $ghdl_out"
[[ $ghdl_out =~ GHDL\ ([0-9][0-9.]*) ]] && ghdl_ver=${BASH_REMATCH[1]} || ghdl_ver=unknown
[[ $ghdl_out =~ ([a-z]+)\ code\ generator ]] && ghdl_backend=${BASH_REMATCH[1]} || ghdl_backend=unknown
echo "ghdl $ghdl_ver ($ghdl_backend backend) ok, ghdl-llvm ok"

# --- gcc and the headers of the co-simulation glue (tools/cosim/*.c, compiled by wrsim.ghdl) ---
if ! command -v gcc >/dev/null 2>&1; then
  echo "gcc missing: installing"
  require_bookworm gcc
  apt_install gcc || die "cannot install gcc with apt-get"
  command -v gcc >/dev/null 2>&1 || die "gcc is still not on PATH after 'apt-get install gcc'"
fi
for header in /usr/lib/ghdl/include/ghdl/vpi_user.h:ghdl-common \
  /usr/share/ngspice/scripts/src/ngspice/cosim.h:"ngspice >= $NGSPICE_MIN (apt-get install -t bookworm-backports ngspice)" \
  /usr/share/ngspice/scripts/src/ngspice/cmtypes.h:"ngspice >= $NGSPICE_MIN (apt-get install -t bookworm-backports ngspice)"; do
  [ -f "${header%%:*}" ] || die "${header%%:*} missing: the co-simulation glue needs it; it comes with package ${header#*:}"
done
echo "gcc $(gcc -dumpversion) and the co-simulation headers ok"

# --- SUNDIALS IDAS, the reference solver's integrator (tools/cosim/reference_idas.c, run by `wrsim bench`) ---
idas_installed() { dpkg-query -W -f='${Status}' libsundials-idas5 2>/dev/null | grep -q 'install ok installed'; }
if ! idas_installed; then
  echo "libsundials-idas5 missing: installing"
  require_bookworm libsundials-idas5
  apt_install libsundials-idas5 || die "cannot install libsundials-idas5 with apt-get"
  idas_installed || die "libsundials-idas5 is still not installed after 'apt-get install libsundials-idas5'"
fi
echo "libsundials-idas5 ok"

# --- Chromium, run headless by the browser check of the HTML report (wrsim.report.browser) ---
if ! command -v chromium >/dev/null 2>&1; then
  echo "chromium missing: installing"
  require_bookworm chromium
  apt_install chromium || die "cannot install chromium with apt-get"
  command -v chromium >/dev/null 2>&1 || die "chromium is still not on PATH after 'apt-get install chromium'"
fi
chromium_out=$(chromium --version </dev/null 2>/dev/null) || die "chromium is installed but 'chromium --version' fails"
[[ $chromium_out =~ Chromium\ ([0-9][0-9.]*) ]] && chromium_ver=${BASH_REMATCH[1]} || chromium_ver=unknown
echo "chromium $chromium_ver ok"

# --- GHDL 5 (Debian trixie), private: the portability check analyses every file as a 1076.1 tool does (--ams) ---
# bookworm's GHDL 2.0 crashes on terminal ports; trixie's needs trixie's C library, which is unpacked beside it and
# used through its own loader, so nothing of the system changes (tests/unit/test_portable.py).
GHDL5=build/native/ghdl5
if ! "$GHDL5/ghdl" --version >/dev/null 2>&1; then
  echo "GHDL 5 for the portability check missing: unpacking Debian trixie's ghdl-mcode into $GHDL5"
  for tool in curl xz dpkg-deb; do command -v $tool >/dev/null 2>&1 || die "$tool is needed to unpack GHDL 5"; done
  mirror=http://deb.debian.org/debian
  tmp=$(mktemp -d)
  curl -fsSL "$mirror/dists/trixie/main/binary-amd64/Packages.xz" -o "$tmp/Packages.xz" ||
    die "cannot download Debian trixie's package index from $mirror"
  xz -dc "$tmp/Packages.xz" > "$tmp/Packages" || die "cannot read Debian trixie's package index"
  for pkg in ghdl-mcode ghdl-common libc6; do
    file=$(awk -v p="$pkg" '$1 == "Package:" {on = ($2 == p)} on && $1 == "Filename:" {print $2; exit}' "$tmp/Packages")
    [ -n "$file" ] || die "Debian trixie has no package $pkg"
    curl -fsSL "$mirror/$file" -o "$tmp/$pkg.deb" || die "cannot download $mirror/$file"
    mkdir -p "$tmp/ghdl5/root"
    dpkg-deb -x "$tmp/$pkg.deb" "$tmp/ghdl5/root" || die "cannot unpack $pkg"
  done
  cat > "$tmp/ghdl5/ghdl" <<'WRAPPER'
#!/bin/sh
# GHDL 5 of Debian trixie with trixie's C library (unpacked beside it by ci/setup.sh), for the portability check.
r=$(cd "$(dirname "$0")" && pwd)/root
l=$r/usr/lib/x86_64-linux-gnu
run() { exec "$l/ld-linux-x86-64.so.2" --library-path "$l:/lib/x86_64-linux-gnu" "$r/usr/bin/ghdl-mcode" "$@"; }
case "$1" in
  -a|-i|-s|--synth) cmd=$1; shift; run "$cmd" --PREFIX="$r/usr/lib/ghdl/mcode/vhdl" "$@" ;;
  *) run "$@" ;;
esac
WRAPPER
  chmod +x "$tmp/ghdl5/ghdl"
  mkdir -p "$(dirname "$GHDL5")"
  rm -rf "$GHDL5"
  mv "$tmp/ghdl5" "$GHDL5"
  rm -rf "$tmp"
  "$GHDL5/ghdl" --version >/dev/null 2>&1 || die "$GHDL5/ghdl does not run"
fi
echo "$("$GHDL5/ghdl" --version | head -n 1) (private, $GHDL5) ok"

# --- Python venv ---
if ! "$VENV/bin/python" -c '' >/dev/null 2>&1; then
  command -v python3 >/dev/null 2>&1 || { echo "python3 missing: installing"; apt_install python3 || die "cannot install python3"; }
  python3 -c 'import sys; sys.exit(sys.version_info < (3, 11))' ||
    die "wrsim needs Python >= 3.11; python3 is $(python3 --version 2>&1)"
  if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    echo "python3 -m venv unusable: installing python3-venv"
    apt_install python3-venv || die "cannot install python3-venv"
  fi
  quietly python3 -m venv --clear "$VENV" || die "python3 -m venv $VENV failed"
  echo "created $VENV"
fi
echo "venv $VENV ($("$VENV/bin/python" --version 2>&1)) ok"

# --- wrsim and its pinned dependencies, reinstalled only when pyproject.toml changed ---
sum=$(sha256sum pyproject.toml | cut -d' ' -f1)
if [ "$(cat "$STAMP" 2>/dev/null || true)" != "$sum" ] || [ ! -x "$VENV/bin/wrsim" ]; then
  echo "pyproject.toml changed since the last install: pip install -e '.[test]'"
  quietly "$VENV/bin/python" -m pip install --disable-pip-version-check -e '.[test]' ||
    die "pip install -e '.[test]' failed (output above)"
  echo "$sum" >"$STAMP"
fi
echo "wrsim $(sed -n 's/^version = "\(.*\)"/\1/p' pyproject.toml) installed in $VENV ok"
