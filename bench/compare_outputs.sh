#!/usr/bin/env bash
# Regression check for refactors: runs every example and analytic case with two radnet
# binaries (or against a directory of reference results) and compares the HDF5 files
# dataset by dataset, bit for bit (tests/compare_h5.py; timings excepted).
#
#   bench/compare_outputs.sh REFERENCE_RADNET CANDIDATE_RADNET [WORK_DIR]
#   bench/compare_outputs.sh --references DIR CANDIDATE_RADNET [WORK_DIR]
#
# A refactor is done when this prints "all N results identical". Keep a reference
# binary before the change: `cp build/radnet /tmp/radnet-before`.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = "--references" ]; then
  references=$2; reference_exe=""; shift 2
else
  reference_exe=$1; references=""; shift
fi
candidate=${1:?usage: compare_outputs.sh REFERENCE_RADNET CANDIDATE_RADNET [WORK_DIR]}
work=${2:-$(mktemp -d)}
mkdir -p "$work/reference" "$work/candidate"
[ -n "$references" ] || references="$work/reference"

failed=0; count=0
for case_file in "$top"/cases/examples/*.yaml "$top"/cases/analytic/*.yaml; do
  label="$(basename "$(dirname "$case_file")")-$(basename "$case_file" .yaml)"
  if [ -n "$reference_exe" ]; then
    "$reference_exe" run "$case_file" -o "$references/$label.h5" -q --threads 2 >/dev/null
  fi
  "$candidate" run "$case_file" -o "$work/candidate/$label.h5" -q --threads 2 >/dev/null
  count=$((count + 1))
  if ! /usr/bin/python3 "$top/tests/compare_h5.py" "$references/$label.h5" "$work/candidate/$label.h5" --quiet; then
    failed=$((failed + 1))
  fi
done
if [ "$failed" -ne 0 ]; then
  echo "$failed of $count results differ (outputs in $work)"
  exit 1
fi
echo "all $count results identical (outputs in $work)"
