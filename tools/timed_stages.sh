#!/usr/bin/env bash
# make test's stages one after another, each timed; a table of the times at the end (and where it stopped).
#   tools/timed_stages.sh MAKE STAGE...
set -uo pipefail
make_cmd=$1
shift
rows=()
start=$(date +%s)
for stage in "$@"; do
  t0=$(date +%s)
  $make_cmd --no-print-directory "$stage"
  status=$?
  rows+=("$(printf '  %-12s %5d s' "$stage" $(( $(date +%s) - t0 )))")
  if [ $status -ne 0 ]; then
    printf 'make test: stage %s failed (exit %d); the stages so far:\n' "$stage" "$status"
    printf '%s\n' "${rows[@]}"
    exit $status
  fi
done
printf 'make test: all passed in %d s:\n' $(( $(date +%s) - start ))
printf '%s\n' "${rows[@]}"
