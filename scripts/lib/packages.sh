# Sourced by scripts/demo.sh and scripts/test.sh (not run on its own).
#
# ensure_packages PKG...: installs, with apt-get, those of the named Debian packages that are not
# installed yet (through sudo when not root); does nothing when all are there.
ensure_packages() {
  local missing=() p sudo=""
  for p in "$@"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  if ((${#missing[@]} == 0)); then
    return 0
  fi
  echo "== installing: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
  fi
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}
