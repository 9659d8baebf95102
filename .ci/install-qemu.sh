#!/usr/bin/env bash
# Installs the QEMU system emulators the firmware tests need (qemu-system-arm for the Cortex-M4F
# `mps2-an386` machine, qemu-system-riscv32 from qemu-system-misc for RISC-V `virt`).
#
# - Does nothing when both are already installed and know their machines.
# - Otherwise tries a plain `apt-get install qemu-system-arm qemu-system-misc`.
# - If that fails (on Debian bookworm it does when qemu-utils from bookworm-backports is already
#   installed: the stable emulators then conflict with it), installs both from
#   <codename>-backports instead, adding that suite with the same mirror as the machine's
#   existing apt sources.
# Exits non-zero if QEMU is still unusable afterwards. Needs root (or sudo).
set -euo pipefail

log() { echo "install-qemu: $*" >&2; }

have_qemu() {
    command -v qemu-system-arm >/dev/null 2>&1 &&
        command -v qemu-system-riscv32 >/dev/null 2>&1 &&
        qemu-system-arm -machine help 2>/dev/null | grep -q '^mps2-an386' &&
        qemu-system-riscv32 -machine help 2>/dev/null | grep -q '^virt'
}

if have_qemu; then
    log "already installed: $(qemu-system-arm --version | head -1)"
    exit 0
fi

SUDO=()
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then
        SUDO=(sudo)
    else
        log "not root and no sudo: cannot install QEMU"
        exit 1
    fi
fi
if ! command -v apt-get >/dev/null 2>&1; then
    log "no apt-get: install qemu-system-arm and qemu-system-riscv32 by hand"
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt_get() { "${SUDO[@]}" apt-get -y -q -o Dpkg::Use-Pty=0 "$@"; }

packages=(qemu-system-arm qemu-system-misc)
log "apt-get update"
apt_get update >/dev/null
log "trying: apt-get install ${packages[*]}"
if apt_get install --no-install-recommends "${packages[@]}" && have_qemu; then
    log "installed: $(qemu-system-arm --version | head -1)"
    exit 0
fi

# Fall back to the distribution's backports suite.
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
if [ -z "$codename" ]; then
    log "plain install failed and the distribution codename is unknown"
    exit 1
fi
suite="$codename-backports"
list=/etc/apt/sources.list.d/backports.list
sources=(/etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources)
if ! grep -qs -- "$suite" "${sources[@]}"; then
    # The Debian mirror the machine already uses (deb822 `URIs:` or one-line `deb URI suite`),
    # not the security archive nor third-party repositories.
    mirror=$( (grep -hs '^URIs:' /etc/apt/sources.list.d/*.sources | awk '{print $2}'
        grep -hs -E '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list |
            awk '{print $2}') | grep -i debian | grep -v -i security | head -1 || true)
    if [ -z "$mirror" ]; then
        log "plain install failed and no apt mirror found to add $suite"
        exit 1
    fi
    log "adding $suite from $mirror to $list"
    echo "deb $mirror $suite main" | "${SUDO[@]}" tee "$list" >/dev/null
    apt_get update >/dev/null
fi
log "trying: apt-get install -t $suite ${packages[*]}"
apt_get install --no-install-recommends -t "$suite" "${packages[@]}"
if have_qemu; then
    log "installed: $(qemu-system-arm --version | head -1)"
    exit 0
fi
log "QEMU still not usable after installing from $suite"
exit 1
