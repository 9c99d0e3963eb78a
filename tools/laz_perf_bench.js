// SPDX-License-Identifier: Apache-2.0
// The reference point for LAZ decoding speed: decodes FILE REPEAT times, record by record, with
// laz-perf 0.0.7 (npm: Hobu's C++ port of the LASzip decoder, built to WebAssembly; the decoder
// that measured ../shared/data/laz/MANIFEST.tsv) and prints points per CPU second, best of 3, in
// laz_bench's format. One thread: laz-perf decodes a file's chunks one after another.
// Usage: node tools/laz_perf_bench.js FILE REPEAT   (tools/bench_laz.sh installs laz-perf)
'use strict';
const fs = require('fs');
const path = require('path');
const { createLazPerf } = require(path.join(__dirname, '..', 'build', 'laz-perf', 'node_modules', 'laz-perf'));

async function main() {
  const [file, repeatText] = process.argv.slice(2);
  const repeat = Number(repeatText);
  if (!file || !(repeat > 0)) throw new Error('usage: node tools/laz_perf_bench.js FILE REPEAT');
  const lazPerf = await createLazPerf();
  const bytes = fs.readFileSync(file);
  const data = lazPerf._malloc(bytes.length);
  lazPerf.HEAPU8.set(bytes, data);
  let best = Infinity;
  let points = 0;
  for (let round = 0; round < 3; ++round) {
    const start = process.cpuUsage();
    points = 0;
    for (let r = 0; r < repeat; ++r) {
      const reader = new lazPerf.LASZip();
      reader.open(data, bytes.length);
      const record = lazPerf._malloc(reader.getPointLength());
      for (let i = reader.getCount(); i > 0; --i) reader.getPoint(record);
      points += reader.getCount();
      lazPerf._free(record);
      reader.delete();
    }
    const used = process.cpuUsage(start);
    best = Math.min(best, (used.user + used.system) / 1e6);
  }
  lazPerf._free(data);
  console.log(`${file} laz-perf threads=1 points=${points} cpu_s=${best.toFixed(3)} ` +
              `Mpoints/cpu-s=${(points / best / 1e6).toFixed(2)}`);
}

main().catch((error) => {
  console.error(`laz_perf_bench: ${error.message}`);
  process.exit(1);
});
