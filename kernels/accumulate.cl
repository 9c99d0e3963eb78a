// Density and colour accumulation: one work-item per raw LAS point record.
//
// Each point is assigned to a cell by comparing its raw 32-bit integer coordinates with cell
// start values the host worked out once per axis (see lasmesh::axis_cells), so the result is the
// same on every device, whatever its floating point. Per cell it adds 1 to the count and the
// stored R, G, B words to the colour sums, as 64-bit sums built from 32-bit atomics: exact and
// independent of the order of the points, and no overflow even for billions of points per cell.
//
// A cell's counters sit together (count, red, green, blue: 4 x 64 bits, one 32-byte block), so a
// point touches one cache line: scattering into a large grid is bound by memory latency.
//
// Compile-time options: -D RGB_OFFSET=n when the point format has colour (byte offset of red).

#ifdef RGB_OFFSET
#define CELL_WORDS 8
#else
#define CELL_WORDS 2
#endif

uint load_u16(global const uchar* p) { return (uint)p[0] | ((uint)p[1] << 8); }

int load_i32(global const uchar* p) {
    return (int)((uint)p[0] | ((uint)p[1] << 8) | ((uint)p[2] << 16) | ((uint)p[3] << 24));
}

// pair[0] is the low word, pair[1] the high word of a little-endian 64-bit counter. Whoever
// makes the low word wrap around carries one into the high word, so the total is exact.
void add64(volatile global uint* pair, uint value) {
    uint old = atomic_add(pair, value);
    if (old > 0xFFFFFFFFu - value) atomic_inc(pair + 1);
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

kernel void accumulate(global const uchar* records, uint count, uint record_length,
                       global const long* starts_x, global const long* starts_y, global const long* starts_z,
                       int nx, int ny, int nz, float per_raw_x, float per_raw_y, float per_raw_z,
                       volatile global uint* cells, volatile global uint* stats) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    global const uchar* record = records + (ulong)i * record_length;
    const int cx = find_cell(load_i32(record), starts_x, nx, per_raw_x);
    const int cy = find_cell(load_i32(record + 4), starts_y, ny, per_raw_y);
    const int cz = find_cell(load_i32(record + 8), starts_z, nz, per_raw_z);
    if (cx < 0 || cy < 0 || cz < 0) {
        add64(stats, 1); // stats[0..1]: points outside the grid
        return;
    }
    volatile global uint* cell = cells + (((ulong)cz * ny + cy) * nx + cx) * CELL_WORDS;
    add64(cell, 1);
#ifdef RGB_OFFSET
    const uint r = load_u16(record + RGB_OFFSET);
    const uint g = load_u16(record + RGB_OFFSET + 2);
    const uint b = load_u16(record + RGB_OFFSET + 4);
    add64(cell + 2, r);
    add64(cell + 4, g);
    add64(cell + 6, b);
    // stats[2]: the largest colour word, which tells 8-bit from 16-bit colour. Read before the
    // atomic so that the one shared word is written only when the maximum actually grows.
    const uint largest = max(r, max(g, b));
    if (largest > stats[2]) atomic_max(stats + 2, largest);
#endif
}
