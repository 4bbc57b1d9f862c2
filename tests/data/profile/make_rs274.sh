#!/bin/sh
# Regenerates the profile programs (LinuxCNC dialect, each plane) and what LinuxCNC's
# interpreter prints for them: run from the repository root after building `talas`.
#   sh tests/data/profile/make_rs274.sh target/debug/talas
set -e
TALAS=${1:-target/debug/talas}
D=tests/data/profile
HOME_DIR=$(mktemp -d)
for plane in g17 g18 g19; do
  "$TALAS" profile $D/square.csv --radius 2 --side outside --plane $plane -o $D/square-$plane.ngc > /dev/null
  "$TALAS" profile $D/s-curve.csv --radius 0.8 --side above --plane $plane -o $D/s-curve-$plane.ngc > /dev/null
  "$TALAS" profile $D/v-notch.csv --radius 1 --side above --plane $plane -o $D/v-notch-$plane.ngc > /dev/null
done
for f in $D/*.ngc; do
  HOME=$HOME_DIR /usr/bin/rs274 -g -t $D/ball.tbl "$f" > "${f%.ngc}.rs274.txt"
done
rm -rf "$HOME_DIR"
