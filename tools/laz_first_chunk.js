// SPDX-License-Identifier: Apache-2.0
// laz_first_chunk.js: writes a smaller, valid LAZ file that holds only the FIRST chunk of a
// chunked LAZ file (LASzip compressor 2 or 3, fixed chunk size): the same header and VLRs, the
// first chunk's compressed bytes copied unchanged, and a new chunk table of one entry.
//
// Why: tests/data/laz ships small real LAZ files so that the LAZ decoder is tested in a plain
// clone. The only real files of point formats 1 (PDAL lone-star.laz, 2.4 MB) and 8 (PDAL
// las_with_several_extra_byte_bloc.laz, 3.2 MB) are too big to ship whole; their first chunk
// (50,000 points) is real LASzip output and small enough. No point is re-encoded, so the test
// data stays what LASzip wrote; only the header, the chunk-table pointer and the table change.
//
// What changes in the header:
//  * point counts: the legacy 32-bit count (left 0 where it was 0, as LAS 1.4 requires for
//    formats 6-10) and, for LAS 1.4, the 64-bit count become the first chunk's point count;
//  * the points-by-return counts are recounted from the chunk's decoded points (return numbers
//    1-5 for the legacy array, 1-15 for the LAS 1.4 array; the legacy array is left 0 where the
//    legacy count is 0; a return number of 0, or above the array, is counted in no entry);
//  * min/max X, Y, Z: the exact bounds of the chunk's points (raw integer * scale + offset);
//  * LAS 1.4 start of first EVLR: where the EVLRs (copied unchanged after the new table) now
//    start. Files with waveform data or COPC files are refused.
//
// The chunk table (LASzip format): the int64 at offset_to_point_data points at it; it is uint32
// version (0), uint32 number of chunks, then the chunk entries entropy-coded with LASzip's
// adaptive arithmetic coder through an integer compressor of 32 bits and 2 contexts (context 0:
// a variable-size chunk's point count, context 1: its byte count, each predicted from the
// previous chunk's; fixed-size chunks store byte counts only). The range encoder, its adaptive
// models and the integer compressor below are written for this tool from the published
// descriptions (M. Isenburg, "LASzip: lossless compression of LiDAR data", 2013; A. Said,
// "Introduction to arithmetic coding - theory and practice", 2003), with the model constants
// that make them decode with lasmesh's own decoder (src/read/arithmetic_decoder.hpp); no code is
// taken from LASzip or laz-perf. A matching decoder is here too, to read the original table
// (the first chunk's size is only known from it) and to check the new one.
//
// laz-perf 0.0.7 (npm) is used only to decode points: the first chunk's points from the
// original file (for the counts and bounds above) and then the whole new file, whose records
// must equal those byte for byte; its ChunkDecoder must also decode the copied chunk alone to
// the same records. The tool also re-encodes the ORIGINAL table's entries with its own encoder
// and reports whether that reproduces LASzip's bytes.
//
// Usage: node tools/laz_first_chunk.js IN.laz OUT.laz
//   (laz-perf: npm install --prefix build/laz-perf --no-audit --no-fund --loglevel=error laz-perf@0.0.7)
'use strict';
const fs = require('fs');
const path = require('path');
const crypto = require('crypto');
const { loadLazPerf } = require('./laz_perf');

const TWO32 = 4294967296;

// ---------------------------------------------------------------------------------------------
// Adaptive models (their state evolves identically in encoder and decoder).

const BM_LENGTH_SHIFT = 13; // bit model: probability of a 0 in 13 bits
const BM_MAX_COUNT = 1 << 13;
const DM_LENGTH_SHIFT = 15; // symbol model: distribution in 15 bits
const DM_MAX_COUNT = 1 << 15;
const MIN_LENGTH = 1 << 24; // renormalise below this interval length

class BitModel {
  constructor() {
    this.zeros = 1; // counted 0s (starts at 1 of 2)
    this.total = 2;
    this.p0 = 1 << (BM_LENGTH_SHIFT - 1); // one half
    this.cycle = 4;
    this.left = 4;
  }
  saw(bit) {
    if (bit === 0) this.zeros += 1;
    if (--this.left === 0) this.refresh();
  }
  refresh() {
    this.total += this.cycle;
    if (this.total > BM_MAX_COUNT) {
      this.total = (this.total + 1) >>> 1;
      this.zeros = (this.zeros + 1) >>> 1;
      if (this.zeros === this.total) this.total += 1;
    }
    const scale = Math.floor(0x80000000 / this.total);
    this.p0 = Math.floor((this.zeros * scale) / 2 ** (31 - BM_LENGTH_SHIFT));
    this.cycle = Math.min((5 * this.cycle) >>> 2, 64);
    this.left = this.cycle;
  }
}

class SymbolModel {
  constructor(symbols) {
    this.n = symbols;
    this.counts = new Array(symbols).fill(1);
    this.cdf = new Array(symbols).fill(0); // cdf[s]: start of s's interval, out of 2^15
    this.total = 0;
    this.cycle = symbols;
    this.refresh();
    this.cycle = this.left = (symbols + 6) >>> 1;
  }
  saw(s) {
    this.counts[s] += 1;
    if (--this.left === 0) this.refresh();
  }
  refresh() {
    this.total += this.cycle;
    if (this.total > DM_MAX_COUNT) {
      this.total = 0;
      for (let s = 0; s < this.n; ++s) {
        this.counts[s] = (this.counts[s] + 1) >>> 1;
        this.total += this.counts[s];
      }
    }
    const scale = Math.floor(0x80000000 / this.total);
    let running = 0;
    for (let s = 0; s < this.n; ++s) {
      this.cdf[s] = Math.floor((scale * running) / 2 ** (31 - DM_LENGTH_SHIFT));
      running += this.counts[s];
    }
    this.cycle = Math.min((5 * this.cycle) >>> 2, (this.n + 6) << 3);
    this.left = this.cycle;
  }
}

// ---------------------------------------------------------------------------------------------
// Range encoder: the interval [low, low + range) of 32-bit integers; bytes leave from the top,
// a carry out of `low` is added to the bytes already written.

class RangeEncoder {
  constructor() {
    this.out = [];
    this.low = 0; // in [0, 2^32)
    this.range = 0xffffffff;
  }
  addToLow(x) {
    this.low += x;
    if (this.low >= TWO32) {
      this.low -= TWO32;
      let i = this.out.length - 1;
      while (i >= 0 && this.out[i] === 0xff) this.out[i--] = 0;
      if (i < 0) throw new Error('carry out of the first byte');
      this.out[i] += 1;
    }
  }
  normalise() {
    while (this.range < MIN_LENGTH) {
      this.out.push(Math.floor(this.low / 2 ** 24));
      this.low = (this.low % 2 ** 24) * 256;
      this.range *= 256;
    }
  }
  bit(model, bit) {
    const split = model.p0 * (this.range >>> BM_LENGTH_SHIFT);
    if (bit === 0) {
      this.range = split;
    } else {
      this.addToLow(split);
      this.range -= split;
    }
    model.saw(bit);
    this.normalise();
  }
  symbol(model, s) {
    const unit = this.range >>> DM_LENGTH_SHIFT;
    const start = model.cdf[s] * unit;
    const end = s === model.n - 1 ? this.range : model.cdf[s + 1] * unit;
    this.addToLow(start);
    this.range = end - start;
    model.saw(s);
    this.normalise();
  }
  // `bits` (1-32) raw bits of `value`, uniformly: more than 19 go as the low 16, then the rest.
  rawBits(bits, value) {
    if (bits > 19) {
      this.rawBits(16, value % 65536);
      this.rawBits(bits - 16, Math.floor(value / 65536));
      return;
    }
    this.range = Math.floor(this.range / 2 ** bits);
    this.addToLow(value * this.range);
    this.normalise();
  }
  // All 32 bits of `low` (a value inside the final interval), so a decoder that reads 4 bytes
  // up front and one per renormalisation stops exactly at the end of the stream.
  finish() {
    for (let i = 3; i >= 0; --i) this.out.push(Math.floor(this.low / 2 ** (8 * i)) % 256);
    return Buffer.from(this.out);
  }
}

// Range decoder: the mirror image; bytes past the end read as 0 and are counted.
class RangeDecoder {
  constructor(bytes) {
    this.bytes = bytes;
    this.pos = 0;
    this.range = 0xffffffff;
    this.value = 0;
    for (let i = 0; i < 4; ++i) this.value = this.value * 256 + this.next();
  }
  next() {
    return this.pos < this.bytes.length ? this.bytes[this.pos++] : (++this.pos, 0);
  }
  normalise() {
    while (this.range < MIN_LENGTH) {
      this.value = (this.value % 2 ** 24) * 256 + this.next();
      this.range *= 256;
    }
  }
  bit(model) {
    const split = model.p0 * (this.range >>> BM_LENGTH_SHIFT);
    let bit;
    if (this.value < split) {
      bit = 0;
      this.range = split;
    } else {
      bit = 1;
      this.value -= split;
      this.range -= split;
    }
    model.saw(bit);
    this.normalise();
    return bit;
  }
  symbol(model) {
    const unit = this.range >>> DM_LENGTH_SHIFT;
    let lo = 0, hi = model.n - 1; // the last s with cdf[s] * unit <= value
    while (lo < hi) {
      const mid = (lo + hi + 1) >>> 1;
      if (model.cdf[mid] * unit <= this.value) lo = mid;
      else hi = mid - 1;
    }
    const s = lo;
    const start = model.cdf[s] * unit;
    const end = s === model.n - 1 ? this.range : model.cdf[s + 1] * unit;
    this.value -= start;
    this.range = end - start;
    model.saw(s);
    this.normalise();
    return s;
  }
  rawBits(bits) {
    if (bits > 19) {
      const low = this.rawBits(16);
      return this.rawBits(bits - 16) * 65536 + low;
    }
    this.range = Math.floor(this.range / 2 ** bits);
    const v = Math.floor(this.value / this.range);
    this.value -= v * this.range;
    this.normalise();
    return v;
  }
}

// ---------------------------------------------------------------------------------------------
// Integer compressor: a value is coded as its correction to a prediction. A correction c falls
// in bucket k (k = 0: c is 0 or 1; k >= 1: c in [2^(k-1)+1, 2^k] or [-(2^k-1), -2^(k-1)]);
// k is coded with a symbol model per context, the position within the bucket (2^k places)
// with a symbol model per k for its top `bitsHigh` bits and raw bits below them. With 32-bit
// values all arithmetic is modulo 2^32 and k = 32 stands for the one correction -2^31.

class IntegerCoder {
  constructor(bits, contexts, bitsHigh = 8) {
    this.bits = bits >= 1 && bits < 32 ? bits : 32;
    this.range = this.bits < 32 ? 2 ** this.bits : TWO32;
    this.minCorr = -(this.range / 2);
    this.maxCorr = this.range / 2 - 1;
    this.bitsHigh = bitsHigh;
    this.kModels = Array.from({ length: contexts }, () => new SymbolModel(this.bits + 1));
    this.zeroModel = new BitModel();
    this.placeModels = []; // index k
  }
  placeModel(k) {
    if (!this.placeModels[k]) this.placeModels[k] = new SymbolModel(2 ** Math.min(k, this.bitsHigh));
    return this.placeModels[k];
  }
  encode(enc, prediction, value, context) {
    let corr = value - prediction; // fold into [minCorr, maxCorr]
    if (corr < this.minCorr) corr += this.range;
    else if (corr > this.maxCorr) corr -= this.range;
    const magnitude = corr <= 0 ? -corr : corr - 1; // 0 for corrections 0 and 1
    const k = magnitude === 0 ? 0 : 32 - Math.clz32(magnitude);
    enc.symbol(this.kModels[context], k);
    if (k === 0) {
      enc.bit(this.zeroModel, corr);
    } else if (k < 32) {
      const place = corr < 0 ? corr + 2 ** k - 1 : corr - 1; // in [0, 2^k)
      if (k <= this.bitsHigh) {
        enc.symbol(this.placeModel(k), place);
      } else {
        const low = k - this.bitsHigh;
        enc.symbol(this.placeModel(k), Math.floor(place / 2 ** low));
        enc.rawBits(low, place % 2 ** low);
      }
    }
  }
  decode(dec, prediction, context) {
    const k = dec.symbol(this.kModels[context]);
    let corr;
    if (k === 0) {
      corr = dec.bit(this.zeroModel);
    } else if (k >= 32) {
      corr = this.minCorr;
    } else {
      let place;
      if (k <= this.bitsHigh) {
        place = dec.symbol(this.placeModel(k));
      } else {
        const low = k - this.bitsHigh;
        place = dec.symbol(this.placeModel(k)) * 2 ** low + dec.rawBits(low);
      }
      corr = place >= 2 ** (k - 1) ? place + 1 : place + 1 - 2 ** k;
    }
    let value = prediction + corr; // back into the value range
    if (this.bits === 32) value = value | 0; // int32, as LASzip stores the entries
    else if (value < 0) value += this.range;
    else if (value >= this.range) value -= this.range;
    return value;
  }
}

// Chunk table entries: [{points, bytes}]; points are coded only for variable-size chunks.
function encodeChunkEntries(entries, variable) {
  const enc = new RangeEncoder();
  const ic = new IntegerCoder(32, 2);
  let lastPoints = 0, lastBytes = 0;
  for (const e of entries) {
    if (variable) {
      ic.encode(enc, lastPoints, e.points, 0);
      lastPoints = e.points;
    }
    ic.encode(enc, lastBytes, e.bytes, 1);
    lastBytes = e.bytes;
  }
  return enc.finish();
}

function decodeChunkEntries(bytes, count, variable, chunkSize) {
  const dec = new RangeDecoder(bytes);
  const ic = new IntegerCoder(32, 2);
  const entries = [];
  let lastPoints = 0, lastBytes = 0;
  for (let i = 0; i < count; ++i) {
    if (variable) lastPoints = ic.decode(dec, lastPoints, 0);
    lastBytes = ic.decode(dec, lastBytes, 1);
    entries.push({ points: variable ? lastPoints : chunkSize, bytes: lastBytes });
  }
  return { entries, used: dec.pos, overrun: dec.pos > bytes.length };
}

function chunkTableBytes(entries, variable) {
  const head = Buffer.alloc(8);
  head.writeUInt32LE(0, 0); // version
  head.writeUInt32LE(entries.length, 4);
  return Buffer.concat([head, encodeChunkEntries(entries, variable)]);
}

// ---------------------------------------------------------------------------------------------
// LAS header and LASzip VLR (LAS 1.0-1.4 header layout; LASzip VLR: laszip encoded / 22204).

function parseLas(buf) {
  if (buf.toString('latin1', 0, 4) !== 'LASF') throw new Error('not a LAS file (no LASF signature)');
  const h = {
    versionMajor: buf[24],
    versionMinor: buf[25],
    headerSize: buf.readUInt16LE(94),
    offsetToPoints: buf.readUInt32LE(96),
    numVlrs: buf.readUInt32LE(100),
    formatRaw: buf[104],
    recordLength: buf.readUInt16LE(105),
    legacyCount: buf.readUInt32LE(107),
    scale: [0, 1, 2].map((i) => buf.readDoubleLE(131 + 8 * i)),
    offset: [0, 1, 2].map((i) => buf.readDoubleLE(155 + 8 * i)),
  };
  h.format = h.formatRaw & 0x3f;
  h.is14 = h.versionMajor === 1 && h.versionMinor >= 4;
  if (h.is14) {
    h.waveformStart = buf.readBigUInt64LE(227);
    h.evlrStart = Number(buf.readBigUInt64LE(235));
    h.numEvlrs = buf.readUInt32LE(243);
    h.count = Number(buf.readBigUInt64LE(247));
  } else {
    h.waveformStart = 0n;
    h.evlrStart = 0;
    h.numEvlrs = 0;
    h.count = h.legacyCount;
  }
  h.vlrs = [];
  let at = h.headerSize;
  for (let i = 0; i < h.numVlrs; ++i) {
    const userId = buf.toString('latin1', at + 2, at + 18).replace(/\0.*$/s, '');
    const recordId = buf.readUInt16LE(at + 18);
    const length = buf.readUInt16LE(at + 20);
    h.vlrs.push({ userId, recordId, at, data: buf.subarray(at + 54, at + 54 + length) });
    at += 54 + length;
  }
  h.vlrEnd = at;
  const lz = h.vlrs.find((v) => v.userId === 'laszip encoded' && v.recordId === 22204);
  if (!lz) throw new Error('no LASzip VLR (laszip encoded/22204): not a LAZ file');
  h.compressor = lz.data.readUInt16LE(0);
  h.chunkSize = lz.data.readUInt32LE(12);
  h.isCopc = h.vlrs.length > 0 && h.vlrs[0].userId === 'copc' && h.vlrs[0].recordId === 1;
  return h;
}

// ---------------------------------------------------------------------------------------------
// laz-perf (decoding only).


// The first `limit` records (all if limit is undefined) of a LAZ file, concatenated.
function lazPerfRecords(lp, bytes, limit) {
  const data = lp._malloc(bytes.length);
  lp.HEAPU8.set(bytes, data);
  const reader = new lp.LASZip();
  try {
    reader.open(data, bytes.length);
    const length = reader.getPointLength();
    const n = limit === undefined ? reader.getCount() : Math.min(limit, reader.getCount());
    const out = Buffer.alloc(n * length);
    const rec = lp._malloc(length);
    for (let i = 0; i < n; ++i) {
      reader.getPoint(rec);
      out.set(lp.HEAPU8.subarray(rec, rec + length), i * length);
    }
    lp._free(rec);
    return { records: out, count: reader.getCount(), length };
  } finally {
    reader.delete();
    lp._free(data);
  }
}

// `n` records decoded from one chunk's bytes alone (laz-perf's ChunkDecoder).
function lazPerfChunk(lp, chunk, format, length, n) {
  const data = lp._malloc(chunk.length);
  lp.HEAPU8.set(chunk, data);
  const decoder = new lp.ChunkDecoder();
  try {
    decoder.open(format, length, data);
    const out = Buffer.alloc(n * length);
    const rec = lp._malloc(length);
    for (let i = 0; i < n; ++i) {
      decoder.getPoint(rec);
      out.set(lp.HEAPU8.subarray(rec, rec + length), i * length);
    }
    lp._free(rec);
    return out;
  } finally {
    decoder.delete();
    lp._free(data);
  }
}

const sha256 = (b) => crypto.createHash('sha256').update(b).digest('hex');

// ---------------------------------------------------------------------------------------------

async function main() {
  const [input, output] = process.argv.slice(2);
  if (!input || !output) throw new Error('usage: node tools/laz_first_chunk.js IN.laz OUT.laz');
  const src = fs.readFileSync(input);
  const h = parseLas(src);
  if (h.compressor !== 2 && h.compressor !== 3) throw new Error(`compressor ${h.compressor}: not chunked`);
  if (h.chunkSize === 0xffffffff) throw new Error('variable-size chunks are not supported');
  if (h.isCopc) throw new Error('COPC file: its hierarchy would have to be rewritten; not supported');
  if (h.waveformStart !== 0n) throw new Error('waveform data: not supported');

  // The original table, read with this tool's decoder.
  const tableOffset = Number(src.readBigInt64LE(h.offsetToPoints));
  if (tableOffset <= h.offsetToPoints || tableOffset + 8 > src.length) throw new Error('no chunk table');
  if (src.readUInt32LE(tableOffset) !== 0) throw new Error('chunk table version is not 0');
  const numChunks = src.readUInt32LE(tableOffset + 4);
  const tableEnd = h.numEvlrs > 0 ? h.evlrStart : src.length;
  const table = decodeChunkEntries(src.subarray(tableOffset + 8, tableEnd), numChunks, false, h.chunkSize);
  if (table.overrun) throw new Error('the original chunk table ends early');
  const firstChunkOffset = h.offsetToPoints + 8;
  const total = table.entries.reduce((a, e) => a + e.bytes, 0);
  if (firstChunkOffset + total !== tableOffset)
    throw new Error(`original chunk sizes add up to ${total}, expected ${tableOffset - firstChunkOffset}`);
  // Re-encode the original entries: how close is this encoder to LASzip's bytes?
  const reencoded = encodeChunkEntries(table.entries, false);
  const original = src.subarray(tableOffset + 8, tableEnd);
  let same = 0;
  while (same < reencoded.length && same < original.length && reencoded[same] === original[same]) ++same;
  console.log(`${input}: ${numChunks} chunks of ${h.chunkSize} points, ${h.count} points; chunk table at ${tableOffset}`);
  console.log(`  original table: ${original.length} coded bytes; this encoder's re-encoding: ${reencoded.length} bytes, ` +
              `the first ${same} identical`);

  const chunkBytes = table.entries[0].bytes;
  const points = Math.min(h.chunkSize, h.count);
  const chunk = src.subarray(firstChunkOffset, firstChunkOffset + chunkBytes);

  // The first chunk's points, as laz-perf decodes them from the original file.
  const lp = await loadLazPerf();
  const first = lazPerfRecords(lp, src, points);
  if (first.length !== h.recordLength) throw new Error('laz-perf disagrees on the record length');
  const alone = lazPerfChunk(lp, chunk, h.format, h.recordLength, points);
  if (!alone.equals(first.records)) throw new Error('laz-perf ChunkDecoder: the chunk alone decodes differently');
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  const byReturn = new Array(16).fill(0);
  for (let i = 0; i < points; ++i) {
    const r = first.records.subarray(i * h.recordLength);
    for (let a = 0; a < 3; ++a) {
      const v = r.readInt32LE(4 * a);
      if (v < min[a]) min[a] = v;
      if (v > max[a]) max[a] = v;
    }
    byReturn[h.format >= 6 ? r[14] & 0x0f : r[14] & 0x07] += 1;
  }

  // The new header.
  const head = Buffer.from(src.subarray(0, h.offsetToPoints)); // header, VLRs and any gap
  if (h.legacyCount !== 0) head.writeUInt32LE(points, 107);
  for (let i = 0; i < 5; ++i) head.writeUInt32LE(h.legacyCount !== 0 ? byReturn[i + 1] : 0, 111 + 4 * i);
  for (let a = 0; a < 3; ++a) {
    head.writeDoubleLE(max[a] * h.scale[a] + h.offset[a], 179 + 16 * a);
    head.writeDoubleLE(min[a] * h.scale[a] + h.offset[a], 187 + 16 * a);
  }
  const newTable = chunkTableBytes([{ points, bytes: chunkBytes }], false);
  const newTableOffset = h.offsetToPoints + 8 + chunkBytes;
  const evlrs = h.numEvlrs > 0 ? src.subarray(h.evlrStart) : Buffer.alloc(0);
  if (h.is14) {
    head.writeBigUInt64LE(h.numEvlrs > 0 ? BigInt(newTableOffset + newTable.length) : 0n, 235);
    head.writeBigUInt64LE(BigInt(points), 247);
    for (let i = 0; i < 15; ++i) head.writeBigUInt64LE(BigInt(byReturn[i + 1]), 255 + 8 * i);
  }
  const pointer = Buffer.alloc(8);
  pointer.writeBigInt64LE(BigInt(newTableOffset));
  const out = Buffer.concat([head, pointer, chunk, newTable, evlrs]);

  // Checks: this tool's decoder reads the new table back; laz-perf decodes the new file to the
  // same records.
  const back = decodeChunkEntries(newTable.subarray(8), 1, false, h.chunkSize);
  if (back.overrun || back.used !== newTable.length - 8 || back.entries[0].bytes !== chunkBytes)
    throw new Error('the new chunk table does not decode back');
  const check = lazPerfRecords(lp, out);
  if (check.count !== points || !check.records.equals(first.records))
    throw new Error('laz-perf decodes the new file differently');
  fs.writeFileSync(output, out);
  console.log(`${output}: ${out.length} bytes; chunk 1: ${points} points in ${chunkBytes} bytes, copied unchanged; ` +
              `new table ${newTable.length} bytes at ${newTableOffset}`);
  console.log(`  bounds (raw) min ${min.join(',')} max ${max.join(',')}; points by return 1-15 ` +
              `${byReturn.slice(1).join(',')}; return number 0: ${byReturn[0]}`);
  console.log(`  points_sha256 ${sha256(check.records)} = first ${points} records of the original (laz-perf 0.0.7)`);
}

main().catch((error) => {
  console.error(`laz_first_chunk: ${error.message}`);
  process.exit(1);
});
