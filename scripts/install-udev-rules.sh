#!/usr/bin/env bash
# Installs hmdlod's udev rules (scripts/70-hmdlod.rules) so the user at the seat can open the
# supported head trackers without root, then reloads udev and re-applies the rules to the USB and
# hidraw devices present. Idempotent: an identical installed file is left alone. Needs root; run
# with sudo. --uninstall removes the file again. After installing, replug the headset if
# `hmdlod devices` still says it cannot open it (rules apply on add; thaytan/OpenHMD #42).
# HMDLOD_UDEV_RULES_DIR and HMDLOD_UDEVADM override the target folder and the udevadm program
# (for testing this script without touching the system).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
src="$here/70-hmdlod.rules"
dir="${HMDLOD_UDEV_RULES_DIR:-/etc/udev/rules.d}"
udevadm="${HMDLOD_UDEVADM:-udevadm}"
dst="$dir/70-hmdlod.rules"

usage() { echo "usage: sudo $0 [--uninstall]"; }
mode=install
case "${1:-}" in
  "") ;;
  --uninstall) mode=uninstall ;;
  -h|--help) usage; exit 0 ;;
  *) usage >&2; exit 1 ;;
esac

if [[ ! -f "$src" ]]; then
  echo "install-udev-rules: $src is missing (run this script from the hmdlod checkout)" >&2
  exit 1
fi
if [[ ! -w "$dir" ]]; then
  echo "install-udev-rules: cannot write to $dir: run it as root, e.g. sudo $0" >&2
  exit 1
fi
if ! command -v "$udevadm" >/dev/null 2>&1; then
  echo "install-udev-rules: $udevadm not found: is udev (systemd-udevd) installed and running?" >&2
  exit 1
fi

changed=0
if [[ $mode == install ]]; then
  if cmp -s "$src" "$dst"; then
    echo "$dst is already up to date"
  else
    install -m 0644 "$src" "$dst.tmp.$$"
    mv -f "$dst.tmp.$$" "$dst"
    echo "installed $dst"
    changed=1
  fi
else
  if [[ -e "$dst" ]]; then
    rm -f "$dst"
    echo "removed $dst"
    changed=1
  else
    echo "$dst is not installed"
  fi
fi

if [[ $changed -eq 1 ]]; then
  "$udevadm" control --reload-rules
  # Re-run the rules for the devices already plugged in ("change" keeps drivers bound).
  "$udevadm" trigger --action=change --subsystem-match=usb --subsystem-match=hidraw
  "$udevadm" settle --timeout=10 || true
  echo "udev rules reloaded and applied; replug the headset if hmdlod devices still cannot open it"
fi
