#!/usr/bin/env bash
# What the fuzz harnesses (fuzz/) need on Debian 12: clang 14 with its
# libFuzzer and sanitizer runtimes. Only for the fuzz path: the library, the
# CLI and the GCC sanitizer build of scripts/test.sh do not need them. Run as
# root; installs only what is missing.
set -euo pipefail
bash "$(dirname "$0")/install_deps.sh" clang-14 libfuzzer-14-dev libclang-rt-14-dev
