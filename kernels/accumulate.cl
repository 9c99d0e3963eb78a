// SPDX-License-Identifier: Apache-2.0
// Sparse accumulation: every point counted into its grid cell, with the sums of its colour words
// and of its position inside the cell, in bricks of B^3 cells allocated on first touch.
//
// Cells are decided by comparing the raw 32-bit LAS integers with cell start values the host
// worked out once per axis (lasmesh::axis_cells), so every device agrees, whatever its floating
// point. All sums are exact 64-bit integers, so the result does not depend on the order in which
// points arrive, the slice size or the device: the pool keeps their low 32 bits, and the rare add
// that carries into the high bits (or brings high bits of its own) appends them to a list, the
// carries, that the host adds back (32-bit words halve the pool; a carry needs 2^32 added to one
// word, so there are few). Two neighbouring words are added with one 64-bit atomic (see
// add_two_words); the device needs cl_khr_int64_base_atomics, which the host checks.
//
// One pass over each slice, and more only where a slice meets bricks not yet in the pool, so no
// work-item ever waits for another (a spin lock on first touch can hang a CPU device that runs a
// work-group's items one after the other):
//   accumulate        adds each point to its cell when the cell's brick is in the pool, and lists
//                     the others (their bricks are new). Consecutive records of a scan often fall
//                     in the same cell, so a work-item sums a run of RUN records privately and
//                     flushes once per change of cell: fewer atomics on acquisition-ordered input.
//   mark_bricks       claims each listed point's brick once (compare-and-swap) and lists it;
//   assign_bricks     gives the new bricks their slots in the pool, after the host made room;
//   accumulate_listed adds the listed points, now that their bricks are there.
// Past the first slices almost every point finds its brick, so the whole slice is read once.
//
// The pool of bricks is up to 12 buffers ("chunks"), so it grows without copying and beyond a
// device's largest allocation: chunk c holds 2^FIRST_BITS << min(c, DOUBLINGS) bricks (they
// double, then stay at the largest allocation), in the order of the bricks' slots.
//
// Compile-time options: BRICK_BITS (B = 2^BRICK_BITS), RUN, FIRST_BITS, DOUBLINGS, POSITION_BITS (21),
// MOMENT_LANES, and RGB_OFFSET=n when the point format has colour (byte offset of red).
//
// Cell record, 32-bit words: the sums of the position inside the cell (raw LAS units from the
// cell's start) in three 21-bit lanes of one 64-bit word (add_lanes), the count, then with colour
// the sums of blue, red and green, then the second moments of the offsets from the cell's start,
// xx, yy, zz, xy, xz, yz (the points' spread inside the cell, which tells a plate scanned on both
// faces from one face; the host bounds the cells so that each sum fits 64 bits), MOMENT_LANES to
// a 64-bit word: three of 21 bits when a point's moment (at most the square of the widest cell
// in raw units) leaves a lane a hundred points or more before it wraps, else two of 32. Each
// word keeps the low bits of its sums. Lanes, because on a CPU each atomic costs about as much
// as a cache miss, and records in an order that rarely puts two in a row in one cell make a
// flush a point: five atomics a point instead of seven (docs/design.md, "Cell record"). A carry
// names its sum, not its word: the cell's place in the pool times CELL_SUMS, plus the sum (x, y,
// z, count, then blue, red, green, then the moments from MOMENT_SUM on).

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#define B (1 << BRICK_BITS)
#define PENDING 0xFFFFFFFFu
#ifdef RGB_OFFSET
#define MOMENT_WORD 6
#define MOMENT_SUM 7
#else
#define MOMENT_WORD 4
#define MOMENT_SUM 4
#endif
// With colour a record takes a whole 64-byte cache line (its sums take 48 bytes): a record
// across two lines costs two cache misses a point where the points rarely share a cell.
#ifdef RGB_OFFSET
#define CELL_WORDS 16
#else
#define CELL_WORDS (MOMENT_WORD + 6)
#endif
#define CELL_SUMS (MOMENT_SUM + 6)

// Fetching a cell's line ahead of its atomic add. OpenCL's prefetch() does nothing on PoCL's CPU
// device, so there the host asks for the compiler's (clang's) own prefetch for writing.
#ifdef CPU_PREFETCH
#define PREFETCH_FOR_WRITE(p) __builtin_prefetch(p, 1)
#else
#define PREFETCH_FOR_WRITE(p) prefetch(p, CELL_WORDS)
#endif

// A 64-bit sum kept as a pair of 32-bit words, low first (the points outside the grid): whoever
// makes the low word wrap carries one into the high word, so the total stays exact.
void add_pair(volatile global uint* sum, ulong value) {
    const uint low = (uint)value;
    const uint old = atomic_add(sum, low);
    const uint high = (uint)(value >> 32) + (old > 0xFFFFFFFFu - low ? 1u : 0u);
    if (high) atomic_add(sum + 1, high);
}

// What the pool's words did not keep of the cells' sums: the 64-bit sum `key` (slot * B^3 *
// CELL_SUMS + cell * CELL_SUMS + sum) gets `delta` added (modulo 2^64). The
// host sized the list so it cannot fill up between two of its reads, and checks that it did not.
typedef struct {
    global ulong* list; // pairs: key, delta
    volatile global uint* count;
    uint capacity;
} Carries;

void list_carry(Carries carries, ulong key, ulong delta) {
    const uint at = atomic_inc(carries.count);
    if (at < carries.capacity) carries.list[2 * at] = key, carries.list[2 * at + 1] = delta;
}

// Adds `value` to the 32-bit word `word` (sum `key`), listing what goes past 32 bits.
void add_word(volatile global uint* word, ulong key, ulong value, Carries carries) {
    const uint low = (uint)value;
    const uint old = atomic_add(word, low);
    const ulong high = (value >> 32) + (old > 0xFFFFFFFFu - low ? 1u : 0u);
    if (high) list_carry(carries, key, high << 32);
}

// Adds `low` and `high` to the 32-bit words words[0] and words[1] (sums key and
// key + 1, 8-byte aligned) with one 64-bit atomic: on a CPU device, when the cell's line is in
// the cache (a coarse grid), each of a flush's atomics costs about as much as the first, and two
// words an atomic took 11% off a run at grid 256 (docs/design.md). What the words do not keep is listed:
// for words[0] the high bits of `low` and its wrap past 2^32, for words[1] the same of `high`
// less the one the wrap of words[0] spilled into it (the 64-bit add carries from lane to lane).
void add_two_words(volatile global uint* words, ulong key, ulong low, ulong high, Carries carries) {
    const ulong old = atom_add((volatile global ulong*)words, (ulong)(uint)low | ((ulong)(uint)high << 32));
    const uint old_low = (uint)old, old_high = (uint)(old >> 32);
    const ulong spill = old_low > 0xFFFFFFFFu - (uint)low ? 1 : 0;
    const ulong low_carry = (low >> 32) + spill;
    const ulong high_wrap = ((ulong)old_high + (uint)high + spill) >> 32;
    const ulong high_delta = (((high >> 32) + high_wrap) << 32) - spill;
    if (low_carry) list_carry(carries, key, low_carry << 32);
    if (high_delta) list_carry(carries, key + 1, high_delta);
}

// Adds a[0..lanes-1] to the `lanes` lanes of `bits` bits each of the 64-bit word at `words`
// (sums key, key + 1, ...) with one atomic, listing what the lanes do not keep: a value's bits
// past `bits`, and a lane's wrap, which the 64-bit add spills into the lane above (that lane
// then lists the one it got too many). The top lane spills into the bits above it, which no sum
// reads, or past the word.
void add_lanes(volatile global uint* words, ulong key, const ulong* a, int lanes, int bits, Carries carries) {
    const ulong mask = (1ul << bits) - 1;
    ulong packed = 0;
    for (int i = 0; i < lanes; ++i) packed |= (a[i] & mask) << (i * bits);
    const ulong old = atom_add((volatile global ulong*)words, packed);
    ulong spill_in = 0;
    for (int i = 0; i < lanes; ++i) {
        const ulong lane = ((old >> (i * bits)) & mask) + (a[i] & mask) + spill_in;
        const ulong spill_out = lane >> bits;
        const ulong delta = (((a[i] >> bits) + spill_out) << bits) - spill_in;
        if (delta) list_carry(carries, key + i, delta);
        spill_in = spill_out;
    }
}

uint load_u16(global const uchar* p) { return (uint)p[0] | ((uint)p[1] << 8); }

int load_i32(global const uchar* p) {
    return (int)((uint)p[0] | ((uint)p[1] << 8) | ((uint)p[2] << 16) | ((uint)p[3] << 24));
}

// The cell whose raw range [starts[i], starts[i+1]) holds r, or -1 outside [starts[0], starts[n]).
// A float estimate lands within a cell or two; the integer comparisons then decide exactly.
int find_cell(long r, global const long* starts, int n, float cells_per_raw) {
    if (r < starts[0] || r >= starts[n]) return -1;
    int i = clamp((int)((float)(r - starts[0]) * cells_per_raw), 0, n - 1);
    while (r < starts[i]) --i;
    while (r >= starts[i + 1]) ++i;
    return i;
}

// The axes' cell starts and sizes, shared by mark_bricks and accumulate.
#define GRID_ARGS                                                                                      \
    global const long *starts_x, global const long *starts_y, global const long *starts_z, int nx, int ny, \
        int nz, float per_raw_x, float per_raw_y, float per_raw_z, uint bricks_x, uint bricks_y

// Cell (x, y, z) of a record; false when it lies outside the grid.
#define LOCATE(record, x, y, z, rx, ry, rz)                                                            \
    const long rx = load_i32(record), ry = load_i32(record + 4), rz = load_i32(record + 8);            \
    const int x = find_cell(rx, starts_x, nx, per_raw_x);                                                \
    const int y = find_cell(ry, starts_y, ny, per_raw_y);                                                \
    const int z = find_cell(rz, starts_z, nz, per_raw_z)

uint brick_of(int x, int y, int z, uint bricks_x, uint bricks_y) {
    return ((uint)(z >> BRICK_BITS) * bricks_y + (uint)(y >> BRICK_BITS)) * bricks_x + (uint)(x >> BRICK_BITS);
}

kernel void mark_bricks(global const uchar* records, global const uint* listed, uint count, uint record_length,
                        GRID_ARGS, volatile global uint* brick_slot, global uint* new_bricks,
                        volatile global uint* counters) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    global const uchar* record = records + (ulong)listed[i] * record_length;
    LOCATE(record, x, y, z, rx, ry, rz);
    const uint b = brick_of(x, y, z, bricks_x, bricks_y);
    // Read first: points of one new brick are usually listed together, and a plain read is cheap.
    if (brick_slot[b] == 0 && atomic_cmpxchg(brick_slot + b, 0u, PENDING) == 0u) new_bricks[atomic_inc(counters + 1)] = b;
}

// Slot s + 1 in the index (0 means no brick); the host zeroed the pool's bricks s already.
kernel void assign_bricks(global const uint* new_bricks, uint count, uint first_slot, global uint* brick_slot) {
    const uint i = get_global_id(0);
    if (i < count) brick_slot[new_bricks[i]] = first_slot + i + 1;
}

#define POOL_ARGS                                                                                      \
    global uint *pool0, global uint *pool1, global uint *pool2, global uint *pool3, global uint *pool4,  \
        global uint *pool5, global uint *pool6, global uint *pool7, global uint *pool8, global uint *pool9, \
        global uint *pool10, global uint *pool11
#define POOL pool0, pool1, pool2, pool3, pool4, pool5, pool6, pool7, pool8, pool9, pool10, pool11

// The first word of the brick in pool slot `slot` (see the chunk layout above).
global uint* brick_words(uint slot, POOL_ARGS) {
    const uint q = (slot >> FIRST_BITS) + 1;
    uint chunk, at;
    if (q < (2u << DOUBLINGS)) {
        chunk = 31 - clz(q); // chunk c starts at slot (2^c - 1) << FIRST_BITS
        at = slot - (((1u << chunk) - 1) << FIRST_BITS);
    } else {
        const uint rest = slot - (((2u << DOUBLINGS) - 1) << FIRST_BITS);
        chunk = DOUBLINGS + 1 + (rest >> (FIRST_BITS + DOUBLINGS));
        at = rest & ((1u << (FIRST_BITS + DOUBLINGS)) - 1);
    }
    global uint* base;
    switch (chunk) {
    case 0: base = pool0; break;
    case 1: base = pool1; break;
    case 2: base = pool2; break;
    case 3: base = pool3; break;
    case 4: base = pool4; break;
    case 5: base = pool5; break;
    case 6: base = pool6; break;
    case 7: base = pool7; break;
    case 8: base = pool8; break;
    case 9: base = pool9; break;
    case 10: base = pool10; break;
    default: base = pool11; break;
    }
    return base + (ulong)at * (B * B * B * CELL_WORDS);
}

// A run's sums for one cell: count, x, y, z, red, green, blue, then xx, yy, zz, xy, xz, yz.
typedef struct {
    ulong n, p[3], r, g, b, m[6];
} RunSums;

// Adds a run's sums to its cell's record, sums key.. (see the record above).
void flush(volatile global uint* record, ulong key, const RunSums* s, Carries carries) {
    if (s->n == 0) return;
    if (s->p[0] | s->p[1] | s->p[2]) add_lanes(record, key, s->p, 3, POSITION_BITS, carries);
#ifdef RGB_OFFSET
    add_two_words(record + 2, key + 3, s->n, s->b, carries);
    if (s->r | s->g) add_two_words(record + 4, key + 5, s->r, s->g, carries);
#else
    add_word(record + 2, key + 3, s->n, carries);
#endif
    for (int k = 0; k < 6; k += MOMENT_LANES) {
        ulong any = 0;
        for (int i = 0; i < MOMENT_LANES; ++i) any |= s->m[k + i];
        if (any)
            add_lanes(record + MOMENT_WORD + 2 * k / MOMENT_LANES, key + MOMENT_SUM + k, s->m + k, MOMENT_LANES,
                      64 / MOMENT_LANES, carries);
    }
}

void clear_sums(RunSums* s) {
    s->n = s->r = s->g = s->b = 0;
    for (int k = 0; k < 3; ++k) s->p[k] = 0;
    for (int k = 0; k < 6; ++k) s->m[k] = 0;
}

// Adds records first..end-1 of the slice, or of the list when `listed` is not null (at most RUN).
// Points whose brick has no slot yet are appended to `deferred` instead (only when reading the
// slice). Two passes over the run: the first finds each record's cell and fetches its line
// towards the cache, the second adds the run's sums cell by cell. On a CPU an atomic add waits
// for its line, and for the atomics before it, so at a fine grid (cells far apart in memory,
// about one point per cell and flush) one cache miss after another would make the whole cost;
// fetched ahead, a run's misses overlap (a fine grid 2x faster on PoCL, docs/design.md).
void accumulate_run(global const uchar* records, global const uint* listed, uint first, uint end, uint record_length,
                    GRID_ARGS, global const uint* brick_slot, POOL_ARGS, Carries carries, volatile global uint* stats,
                    global uint* deferred, volatile global uint* deferred_count) {
    // Each record's cell: its words in the pool (0 when outside the grid or its brick is new), its
    // place in the pool's words and the point's offsets from the cell's start.
    global uint* cells[RUN];
    ulong keys[RUN];
    uint offsets[RUN][3];
    uint outside = 0, largest = 0;
    const uint n_records = end - first;
    for (uint k = 0; k < n_records; ++k) {
        const uint r = listed ? listed[first + k] : first + k;
        global const uchar* record = records + (ulong)r * record_length;
        LOCATE(record, x, y, z, rx, ry, rz);
        cells[k] = 0;
        if (x < 0 || y < 0 || z < 0) {
            ++outside;
            continue;
        }
        const uint slot = brick_slot[brick_of(x, y, z, bricks_x, bricks_y)];
        if (!slot) {
            if (deferred) deferred[atomic_inc(deferred_count)] = r;
            continue;
        }
        const uint in_brick = (((uint)z & (B - 1)) * B + ((uint)y & (B - 1))) * B + ((uint)x & (B - 1));
        global uint* cell = brick_words(slot - 1, POOL) + in_brick * CELL_WORDS;
        PREFETCH_FOR_WRITE(cell);
        cells[k] = cell;
        keys[k] = ((ulong)(slot - 1) * (B * B * B) + in_brick) * CELL_SUMS;
        offsets[k][0] = (uint)(rx - starts_x[x]);
        offsets[k][1] = (uint)(ry - starts_y[y]);
        offsets[k][2] = (uint)(rz - starts_z[z]);
    }
    // The current cell and its sums, flushed once per change of cell.
    global uint* cell = 0;
    ulong key = 0;
    RunSums s;
    clear_sums(&s);
    for (uint k = 0; k < n_records; ++k) {
        if (!cells[k]) continue;
        if (cells[k] != cell) {
            flush(cell, key, &s, carries);
            clear_sums(&s);
            cell = cells[k], key = keys[k];
        }
        const ulong ox = offsets[k][0], oy = offsets[k][1], oz = offsets[k][2];
        s.n += 1;
        s.p[0] += ox;
        s.p[1] += oy;
        s.p[2] += oz;
        s.m[0] += ox * ox;
        s.m[1] += oy * oy;
        s.m[2] += oz * oz;
        s.m[3] += ox * oy;
        s.m[4] += ox * oz;
        s.m[5] += oy * oz;
#ifdef RGB_OFFSET
        const uint r = listed ? listed[first + k] : first + k;
        global const uchar* record = records + (ulong)r * record_length;
        const uint red = load_u16(record + RGB_OFFSET), green = load_u16(record + RGB_OFFSET + 2),
                   blue = load_u16(record + RGB_OFFSET + 4);
        s.r += red;
        s.g += green;
        s.b += blue;
        largest = max(largest, max(red, max(green, blue)));
#endif
    }
    flush(cell, key, &s, carries);
    // stats[0..1]: points outside the grid, a 64-bit sum; stats[2]: the largest colour word, which
    // tells 8-bit from 16-bit colour (read first: the shared word is written only when it grows).
    if (outside) add_pair(stats, outside);
    if (largest > stats[2]) atomic_max(stats + 2, largest);
}

// counters[0]: points deferred; [1]: bricks new (mark_bricks); [2]: carries listed.
kernel void accumulate(global const uchar* records, uint count, uint record_length, GRID_ARGS,
                       global const uint* brick_slot, POOL_ARGS, global ulong* carry_list, uint carry_capacity,
                       volatile global uint* stats, global uint* deferred, volatile global uint* counters) {
    const uint first = get_global_id(0) * RUN;
    if (first >= count) return;
    const Carries carries = {carry_list, counters + 2, carry_capacity};
    accumulate_run(records, 0, first, min(first + RUN, count), record_length, starts_x, starts_y, starts_z, nx, ny, nz,
                   per_raw_x, per_raw_y, per_raw_z, bricks_x, bricks_y, brick_slot, POOL, carries, stats, deferred,
                   counters);
}

kernel void accumulate_listed(global const uchar* records, global const uint* listed, uint count, uint record_length,
                              GRID_ARGS, global const uint* brick_slot, POOL_ARGS, global ulong* carry_list,
                              uint carry_capacity, volatile global uint* stats, volatile global uint* counters) {
    const uint first = get_global_id(0) * RUN;
    if (first >= count) return;
    const Carries carries = {carry_list, counters + 2, carry_capacity};
    accumulate_run(records, listed, first, min(first + RUN, count), record_length, starts_x, starts_y, starts_z, nx, ny,
                   nz, per_raw_x, per_raw_y, per_raw_z, bricks_x, bricks_y, brick_slot, POOL, carries, stats, 0, 0);
}
