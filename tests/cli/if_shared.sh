#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs COMMAND... when the shared corpus beside the checkout (SOURCE_DIR/../shared, or
# $LASMESH_SHARED) is there; otherwise exits 77, which CTest reports as Skipped, not Passed.
# Usage: if_shared.sh SOURCE_DIR COMMAND...
shared=${LASMESH_SHARED:-$1/../shared}
if [ ! -f "$shared/data/las/MANIFEST.tsv" ] || [ ! -f "$shared/data/laz/MANIFEST.tsv" ]; then
  echo "skipped: the shared corpus ($shared/data/las and data/laz) is absent"
  exit 77
fi
shift
exec "$@"
