// SPDX-License-Identifier: Apache-2.0
// laz-perf, the reference LAZ decoder (WebAssembly, from npm into build/laz-perf by tools/test.sh),
// loaded once for the scripts that measure LAZ facts with it.
'use strict';
const fs = require('fs');
const path = require('path');

async function loadLazPerf() {
  const dir = path.join(__dirname, '..', 'build', 'laz-perf', 'node_modules', 'laz-perf');
  if (!fs.existsSync(dir)) {
    throw new Error('laz-perf is not installed: npm install --prefix build/laz-perf --no-audit --no-fund ' +
                    '--loglevel=error laz-perf@0.0.7');
  }
  const { createLazPerf } = require(dir);
  return createLazPerf();
}

module.exports = { loadLazPerf };
