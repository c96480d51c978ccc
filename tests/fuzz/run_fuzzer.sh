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
# -seed=1: the same sequence of inputs in every run, so that the gate passes or
# fails alike on every change (it may reach further on a faster machine).
# Explore with other seeds by hand (tests/fuzz/README.md).
# -timeout: one input taking longer than 10 s is a hang (a finding).
# -rss_limit_mb: more than 2 GB for inputs of a few KB is a finding.
"$fuzzer" -seed=1 -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "$@"
