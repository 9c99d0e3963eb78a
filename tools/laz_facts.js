// SPDX-License-Identifier: Apache-2.0
// laz_facts.js: measures the facts of LAZ files that tests/data/laz/MANIFEST.tsv records, with an
// independent decoder: laz-perf 0.0.7 (npm; Hobu's C++ port of the LASzip decoder, built to
// WebAssembly). Header, LASzip-VLR and chunk-table-header facts are read here from the bytes
// (LAS 1.0-1.4 header layout, LASzip VLR laszip encoded/22204, COPC info VLR copc/1); point
// facts come from the records laz-perf decodes. Nothing comes from lasmesh, so a test can
// compare lasmesh's decoder with these facts, or recompute them with this script.
//
// Usage: node tools/laz_facts.js FILE...                print the measured columns as TSV
//        node tools/laz_facts.js --check DIR           recompute DIR/MANIFEST.tsv's measured columns
//                                                       for its files; exit 1 if any differs
//        node tools/laz_facts.js --write DIR           rewrite them (the other columns are kept)
//        node tools/laz_facts.js --prefix-sha N FILE   SHA-256 of the first N records laz-perf decodes
// laz-perf: npm install --prefix build/laz-perf --no-audit --no-fund --loglevel=error laz-perf@0.0.7
//
// Columns: file_size, sha256 (of the file); las_version; point_format (compression bits cleared);
// record_length; laszip_compressor (1 pointwise, 2 pointwise-chunked, 3 layered-chunked);
// chunk_size (points per chunk, or variable (0xFFFFFFFF)); num_chunks (the count in the chunk
// table's header); is_copc (first VLR is copc/1); point_count (records laz-perf decoded);
// points_sha256 (SHA-256 of those records concatenated, record_length bytes each, extra bytes
// included); min_raw, max_raw (stored 32-bit X,Y,Z integers); rgb_min, rgb_max (per-channel
// 16-bit R,G,B, for formats 2, 3, 5, 7, 8, 10; - otherwise).
'use strict';
const fs = require('fs');
const path = require('path');
const crypto = require('crypto');
const { loadLazPerf } = require('./laz_perf');

const COLUMNS = ['file_size', 'sha256', 'las_version', 'point_format', 'record_length', 'laszip_compressor',
  'chunk_size', 'num_chunks', 'is_copc', 'point_count', 'points_sha256', 'min_raw', 'max_raw', 'rgb_min', 'rgb_max'];
const COMPRESSORS = { 0: '0 none', 1: '1 pointwise', 2: '2 pointwise-chunked', 3: '3 layered-chunked' };
const RGB_OFFSET = { 2: 20, 3: 28, 5: 28, 7: 30, 8: 30, 10: 30 };

const sha256 = (b) => crypto.createHash('sha256').update(b).digest('hex');


// Calls visit(record bytes, index) for the first `limit` records (all when undefined).
function decodeRecords(lp, bytes, limit, visit) {
  const data = lp._malloc(bytes.length);
  lp.HEAPU8.set(bytes, data);
  const reader = new lp.LASZip();
  try {
    reader.open(data, bytes.length);
    const length = reader.getPointLength();
    const n = limit === undefined ? reader.getCount() : Math.min(limit, reader.getCount());
    const rec = lp._malloc(length);
    for (let i = 0; i < n; ++i) {
      reader.getPoint(rec);
      visit(lp.HEAPU8.subarray(rec, rec + length), i);
    }
    lp._free(rec);
    return { count: n, length, format: reader.getPointFormat() };
  } finally {
    reader.delete();
    lp._free(data);
  }
}

function headerFacts(buf) {
  if (buf.toString('latin1', 0, 4) !== 'LASF') throw new Error('not a LAS file');
  const headerSize = buf.readUInt16LE(94);
  const offsetToPoints = buf.readUInt32LE(96);
  const numVlrs = buf.readUInt32LE(100);
  const vlrs = [];
  for (let i = 0, at = headerSize; i < numVlrs; ++i) {
    const userId = buf.toString('latin1', at + 2, at + 18).replace(/\0.*$/s, '');
    const recordId = buf.readUInt16LE(at + 18);
    const length = buf.readUInt16LE(at + 20);
    vlrs.push({ userId, recordId, at, data: buf.subarray(at + 54, at + 54 + length) });
    at += 54 + length;
  }
  const f = {
    las_version: `${buf[24]}.${buf[25]}`,
    point_format: String(buf[104] & 0x3f),
    record_length: String(buf.readUInt16LE(105)),
    is_copc: vlrs.length > 0 && vlrs[0].userId === 'copc' && vlrs[0].recordId === 1 && vlrs[0].at === 375 ? 'yes' : 'no',
  };
  const lz = vlrs.find((v) => v.userId === 'laszip encoded' && v.recordId === 22204);
  if (!lz) {
    Object.assign(f, { laszip_compressor: '-', chunk_size: '-', num_chunks: '-' });
    return f;
  }
  const compressor = lz.data.readUInt16LE(0);
  const chunkSize = lz.data.readUInt32LE(12);
  f.laszip_compressor = COMPRESSORS[compressor] || String(compressor);
  f.chunk_size = chunkSize === 0xffffffff ? 'variable (0xFFFFFFFF)' : String(chunkSize);
  f.num_chunks = '-';
  if (compressor === 2 || compressor === 3) {
    const tableOffset = Number(buf.readBigInt64LE(offsetToPoints));
    if (tableOffset > offsetToPoints && tableOffset + 8 <= buf.length) f.num_chunks = String(buf.readUInt32LE(tableOffset + 4));
    else f.num_chunks = 'no table';
  }
  return f;
}

async function facts(lp, file) {
  const buf = fs.readFileSync(file);
  const f = { file_size: String(buf.length), sha256: sha256(buf), ...headerFacts(buf) };
  const hash = crypto.createHash('sha256');
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  const rgbMin = [Infinity, Infinity, Infinity], rgbMax = [-Infinity, -Infinity, -Infinity];
  const rgb = RGB_OFFSET[Number(f.point_format)];
  const decoded = decodeRecords(lp, buf, undefined, (r) => {
    hash.update(r);
    for (let a = 0; a < 3; ++a) {
      const v = r[4 * a] | (r[4 * a + 1] << 8) | (r[4 * a + 2] << 16) | (r[4 * a + 3] << 24);
      if (v < min[a]) min[a] = v;
      if (v > max[a]) max[a] = v;
    }
    if (rgb !== undefined) {
      for (let c = 0; c < 3; ++c) {
        const v = r[rgb + 2 * c] | (r[rgb + 2 * c + 1] << 8);
        if (v < rgbMin[c]) rgbMin[c] = v;
        if (v > rgbMax[c]) rgbMax[c] = v;
      }
    }
  });
  if (String(decoded.length) !== f.record_length) throw new Error(`${file}: laz-perf's record length ${decoded.length} differs`);
  const some = decoded.count > 0;
  Object.assign(f, {
    point_count: String(decoded.count),
    points_sha256: hash.digest('hex'),
    min_raw: some ? min.join(',') : '-',
    max_raw: some ? max.join(',') : '-',
    rgb_min: rgb !== undefined && some ? rgbMin.join(',') : '-',
    rgb_max: rgb !== undefined && some ? rgbMax.join(',') : '-',
  });
  return f;
}

function readManifest(file) {
  const lines = fs.readFileSync(file, 'utf8').split('\n').filter((l) => l.length > 0);
  const header = lines[0].split('\t');
  const rows = lines.slice(1).map((l) => {
    const cells = l.split('\t');
    return Object.fromEntries(header.map((h, i) => [h, cells[i] === undefined ? '' : cells[i]]));
  });
  return { header, rows };
}

async function main() {
  const args = process.argv.slice(2);
  const usage = 'usage: node tools/laz_facts.js FILE... | --check DIR | --write DIR | --prefix-sha N FILE';
  if (args.length === 0) throw new Error(usage);
  const lp = await loadLazPerf();
  if (args[0] === '--prefix-sha') {
    const n = Number(args[1]);
    if (!(n >= 0) || !args[2]) throw new Error(usage);
    const hash = crypto.createHash('sha256');
    const d = decodeRecords(lp, fs.readFileSync(args[2]), n, (r) => hash.update(r));
    console.log(`${hash.digest('hex')}  first ${d.count} records of ${args[2]}`);
    return;
  }
  if (args[0] === '--check' || args[0] === '--write') {
    const dir = args[1];
    if (!dir) throw new Error(usage);
    const manifest = path.join(dir, 'MANIFEST.tsv');
    const { header, rows } = readManifest(manifest);
    for (const c of COLUMNS) if (!header.includes(c)) throw new Error(`${manifest} has no column ${c}`);
    let passed = 0, failed = 0;
    for (const row of rows) {
      const f = await facts(lp, path.join(dir, row.file));
      const diffs = COLUMNS.filter((c) => row[c] !== f[c]);
      if (args[0] === '--write') {
        Object.assign(row, f);
        continue;
      }
      if (diffs.length === 0) {
        ++passed;
        console.log(`ok ${row.file}`);
      } else {
        ++failed;
        for (const c of diffs) console.log(`FAIL ${row.file}: ${c} is ${f[c]}, MANIFEST.tsv says ${row[c]}`);
      }
    }
    if (args[0] === '--write') {
      const text = [header.join('\t'), ...rows.map((r) => header.map((h) => r[h]).join('\t'))].join('\n') + '\n';
      fs.writeFileSync(manifest, text);
      console.log(`${manifest}: ${rows.length} rows written`);
      return;
    }
    console.log(`${passed} passed, ${failed} failed`);
    if (failed > 0) process.exitCode = 1;
    return;
  }
  console.log(['file', ...COLUMNS].join('\t'));
  for (const file of args) {
    const f = await facts(lp, file);
    console.log([path.basename(file), ...COLUMNS.map((c) => f[c])].join('\t'));
  }
}

main().catch((error) => {
  console.error(`laz_facts: ${error.message}`);
  process.exit(1);
});
