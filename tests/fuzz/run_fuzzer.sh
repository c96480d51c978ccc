#!/bin/sh
# Runs a libFuzzer binary for a bounded time and fails on any finding.
#
#   run_fuzzer.sh FUZZER SECONDS ARTIFACT_DIR [-flag=value...] CORPUS_DIR...
#
# New inputs go to a temporary folder (libFuzzer writes to its first corpus
# folder only), so the committed corpus is read, never modified. A crashing
# input is saved in ARTIFACT_DIR; add it to tests/fuzz/regressions/ once fixed.
set -eu
fuzzer=$1 seconds=$2 artifacts=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$artifacts"
# -timeout: one input taking longer than 10 s is a hang (a finding).
# -rss_limit_mb: more than 2 GB for inputs of a few KB is a finding.
"$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "$@"
