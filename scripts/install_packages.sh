#!/usr/bin/env bash
# Installs the Debian packages given as arguments that are not installed yet (no recommends).
# Used by scripts/setup.sh (the project's packages) and for the fuzzing build's clang
# (docs/fuzzing.md). PREPREG_SKIP_APT=1 skips it (machines where apt is not usable).
set -euo pipefail
[[ "${PREPREG_SKIP_APT:-0}" == 1 ]] && exit 0
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0
SUDO=""
[[ $(id -u) -ne 0 ]] && SUDO="sudo"
echo "install_packages: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
