# SPDX-License-Identifier: Apache-2.0
# Shared by the benchmark scripts (sourced): best wall time in seconds of 3 runs of a command.
best() {
  local best=999999
  for _ in 1 2 3; do
    local start end t
    start=$(date +%s.%N); "$@" > /dev/null; end=$(date +%s.%N)
    t=$(echo "$end - $start" | bc -l)
    best=$(echo "if ($t < $best) $t else $best" | bc -l)
  done
  echo "$best"
}
