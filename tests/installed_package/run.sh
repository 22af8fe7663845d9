#!/usr/bin/env bash
# Installs the build tree's geometry library to a scratch prefix, then
# configures, builds and runs a consumer project against it.
set -euo pipefail
build=$1; source=$(cd "$(dirname "$0")" && pwd)
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
cmake --install "$build" --prefix "$scratch/prefix" --component Unspecified >/dev/null
cmake -S "$source" -B "$scratch/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$scratch/prefix" >/dev/null
cmake --build "$scratch/consumer" >/dev/null
"$scratch/consumer/geometry_consumer"
