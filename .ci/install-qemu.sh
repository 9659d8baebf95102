#!/usr/bin/env bash
# Installs qemu-system-arm and qemu-system-misc (riscv32) if missing. On Debian bookworm images
# that carry qemu-utils from bookworm-backports, the plain install conflicts; fall back to
# installing the system emulators from bookworm-backports too.
set -euo pipefail
if command -v qemu-system-arm >/dev/null && command -v qemu-system-riscv32 >/dev/null; then
  qemu-system-arm --version | head -1
  exit 0
fi
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
if ! $SUDO apt-get install -y -q qemu-system-arm qemu-system-misc; then
  echo "plain install failed; trying bookworm-backports"
  echo 'deb http://deb.debian.org/debian bookworm-backports main' | $SUDO tee /etc/apt/sources.list.d/backports.list
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q -t bookworm-backports qemu-system-arm qemu-system-misc
fi
qemu-system-arm --version | head -1
