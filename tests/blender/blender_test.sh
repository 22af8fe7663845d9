#!/usr/bin/env bash
# Runs one Blender test script headless with the add-on installed from its
# zip into a throw-away user folder:
#   blender_test.sh ISOTRACE_BINARY ADDON_ZIP SCRIPT.py
# Skips (exit 0, "blender_test: SKIPPED") without Blender; .ci/setup installs
# it when ISOTRACE_INSTALL_BLENDER=1, as .ci/run asks.
set -euo pipefail
binary=$1 zip=$2 script=$3
if ! command -v blender >/dev/null; then
  echo "blender_test: SKIPPED: Blender is not installed (Debian: apt-get install blender, or .ci/setup with ISOTRACE_INSTALL_BLENDER=1)"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export BLENDER_USER_SCRIPTS=$work/scripts BLENDER_USER_CONFIG=$work/config
export ISOTRACE_BINARY=$binary ISOTRACE_TEST_FOLDER=$work ISOTRACE_ADDON_ZIP=$zip
export PYTHONPATH=$(dirname "$0")${PYTHONPATH:+:$PYTHONPATH}
blender -b --factory-startup -noaudio --python-exit-code 1 --python "$script" 2>&1
