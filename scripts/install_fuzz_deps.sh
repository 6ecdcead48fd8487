#!/usr/bin/env bash
# What the fuzz harnesses (fuzz/) need on Debian 12: clang 14 with its
# libFuzzer and sanitizer runtimes. Only for the fuzz path: the library, the
# CLI and the GCC sanitizer build of scripts/test.sh do not need them. Run as
# root; installs only what is missing.
set -euo pipefail
packages=(clang-14 libfuzzer-14-dev libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
