#!/bin/bash
# Install the Debian packages named that are not installed yet (apt's output to LOG).
#   tools/apt_install.sh LOG "WHAT (TIME)" PACKAGE...
set -euo pipefail
log=$1 what=$2
shift 2
missing=""
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
sudo=""
[ "$(id -u)" = 0 ] || sudo=sudo
mkdir -p "$(dirname "$log")"
echo "Installing $what; log in $log:$missing"
# shellcheck disable=SC2086  # the package names are words
{ $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq \
    --no-install-recommends $missing; } > "$log" 2>&1 \
  || { tail -n 30 "$log"; echo "apt-get failed: see $log"; exit 1; }
