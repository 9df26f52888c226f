/* antipinch.c: the anti-pinch algorithm of vhdl/digital/antipinch.vhd written in C, the example of an algorithm
 * compiled into the loop (docs/anti-pinch.md, "Algorithm interface"). ecu_software with the generic algorithm = 1
 * calls these four functions through GHDL's VHPIDIRECT instead of the VHDL package's own code; wrsim compiles
 * this file and links it into the digital unit (the "-- c source:" line of antipinch.vhd).
 *
 * The algorithm and its integer arithmetic are those of the VHDL twin, so both give the same decisions: the
 * speed over the last revolution (4 Hall-A edges) against the no-load speed at the measured supply voltage,
 * deficit = rpm_per_volt*U - n [rpm], compared with a reference over position learned when a run up stalls at
 * the top; a pinch is deficit - reference > threshold (+ a start-up term), see antipinch.vhd.
 *
 * State: static, one copy per digital-unit instance (ngspice's loader gives every d_cosim instance its own copy
 * of the library). Arguments are VHDL integers (32 bits); booleans are passed as 0/1. */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define MAX_BINS 512   /* antipinch.vhd: ap_max_bins */
#define MAX_RUN 4096   /* antipinch.vhd: ap_max_run */
#define US_PER_MIN 60000000

static struct {
    int32_t rpm_per_volt, threshold_rpm, startup_rpm, start_us, blank_edges, edges_per_bin, reference_bins,
        learn_shift, max_run_edges, zone_edges;
} cfg;

static int32_t ref[MAX_BINS];
static bool ref_ok[MAX_BINS];
static int32_t lowest = -1;
static int32_t run_def[MAX_RUN];
static bool run_ok[MAX_RUN];
static int32_t edge_t[4];
static int32_t run_start, run_pos;
static int32_t shown;   /* the load above the reference at the last compared edge [rpm], held until the next */

/* A run starts at t_us [us] and position pos [edges below the top]; the ECU's generics come with it. */
void wrsim_ap_start(int32_t t_us, int32_t pos, int32_t rpm_per_volt, int32_t threshold_rpm, int32_t startup_rpm,
                    int32_t start_us, int32_t blank_edges, int32_t edges_per_bin, int32_t reference_bins,
                    int32_t learn_shift, int32_t max_run_edges, int32_t zone_edges)
{
    cfg.rpm_per_volt = rpm_per_volt;
    cfg.threshold_rpm = threshold_rpm;
    cfg.startup_rpm = startup_rpm;
    cfg.start_us = start_us;
    cfg.blank_edges = blank_edges;
    cfg.edges_per_bin = edges_per_bin;
    cfg.reference_bins = reference_bins > MAX_BINS ? MAX_BINS : reference_bins;
    cfg.learn_shift = learn_shift;
    cfg.max_run_edges = max_run_edges > MAX_RUN ? MAX_RUN : max_run_edges;
    cfg.zone_edges = zone_edges;
    run_start = t_us;
    run_pos = pos;
    memset(run_ok, 0, sizeof run_ok);
}

/* The reference at position p, linear between the centres of learned bins; false where none covers p. */
static bool lookup(int32_t p, int32_t *reference)
{
    *reference = 0;
    if (p < 0)
        return false;
    int32_t b = p / cfg.edges_per_bin;
    if (b > lowest)
        b = lowest;
    if (b < 0 || !ref_ok[b])
        return false;
    *reference = ref[b];
    int32_t off = p - b * cfg.edges_per_bin - cfg.edges_per_bin / 2;
    if (off >= 0 && b < lowest) {
        if (ref_ok[b + 1])
            *reference = ref[b] + (ref[b + 1] - ref[b]) * off / cfg.edges_per_bin;
    } else if (off < 0 && b > 0) {
        if (ref_ok[b - 1])
            *reference = ref[b] + (ref[b] - ref[b - 1]) * off / cfg.edges_per_bin;
    }
    return true;
}

/* A Hall-A edge in the run's direction; returns 1 for a pinch (reverse now). current_ma: the motor current [mA]
 * (INT32_MIN, antipinch.vhd's ap_no_current, where the ECU measures none), which this algorithm does not read. */
int32_t wrsim_ap_edge(int32_t t_us, int32_t pos, int32_t run_edges, int32_t up, int32_t supply_dv,
                      int32_t current_ma, int32_t normalized)
{
    (void)current_ma;
    int32_t pinch = 0, slot = run_edges % 4;
    if (up && run_edges > 4 && supply_dv >= 0 && t_us > edge_t[slot]) {
        int32_t rpm = US_PER_MIN / (t_us - edge_t[slot]);
        int32_t deficit = cfg.rpm_per_volt * supply_dv / 10 - rpm;
        if (run_edges > cfg.blank_edges) {
            int32_t travelled = run_pos - pos;
            if (t_us - run_start >= cfg.start_us && travelled >= 0 && travelled < cfg.max_run_edges) {
                run_def[travelled] = deficit;
                run_ok[travelled] = true;
            }
            if (normalized && pos > cfg.zone_edges) {
                int32_t reference, limit = cfg.threshold_rpm;
                bool found = lookup(pos, &reference);
                if (t_us - run_start < cfg.start_us)
                    limit += cfg.startup_rpm * ((cfg.start_us - (t_us - run_start)) / 1000) / (cfg.start_us / 1000);
                pinch = found && deficit - reference > limit;
                if (found)
                    shown = deficit - reference;
            }
        }
    }
    edge_t[slot] = t_us;
    return pinch;
}

/* A run up ended in a stall at the top, `shift` edges from the run's position scale: learn the reference. */
void wrsim_ap_top(int32_t shift)
{
    static int32_t sums[MAX_BINS], counts[MAX_BINS];
    memset(sums, 0, sizeof sums);
    memset(counts, 0, sizeof counts);
    for (int32_t r = 0; r < cfg.max_run_edges; r++) {
        if (!run_ok[r])
            continue;
        int32_t p = run_pos - r - shift;
        if (p >= 0 && p < cfg.reference_bins * cfg.edges_per_bin) {
            sums[p / cfg.edges_per_bin] += run_def[r];
            counts[p / cfg.edges_per_bin]++;
        }
    }
    for (int32_t k = 0; k < cfg.reference_bins; k++) {
        if (counts[k] == 0)
            continue;
        int32_t mean = sums[k] / counts[k];
        if (ref_ok[k]) {
            ref[k] += (mean - ref[k]) / (1 << cfg.learn_shift);
        } else {
            ref[k] = mean;
            ref_ok[k] = true;
        }
        if (k > lowest)
            lowest = k;
    }
}

/* What the last compared edge measured above the reference [rpm] (0 before the first). */
int32_t wrsim_ap_load(void)
{
    return shown;
}
