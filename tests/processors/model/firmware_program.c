/* The firmware side of the equivalence test: the C header `gyrocal export --format c-header`
 * writes, compiled by the system C compiler into this program, fed the samples CSV `gyrocal
 * export --format samples` writes, one raw sample at a time in file order, as firmware would.
 *
 * Build: cc -std=c99 -I DIR -DGYROCAL_TEST_INIT=gyrocal_<sensor>_init firmware_program.c -lm
 * (DIR holds the header as gyrocal_coeffs.h). Usage: program SAMPLES.csv
 * Prints the header "time_s,rate_dps,angle_deg", then one such line per computed sample (17
 * significant digits: the double read back exactly) and "not_computable,N" last. Exit 1 on a file
 * it cannot read.
 *
 * The time of a sample and its power-on time follow the CSV format's definitions:
 * utime = 1e15 us + round(time_s * 1e6), power-on = utime - round(time_since_power_s * 1e6),
 * given to the trackers whenever it changes (a new power cycle); without the column the trackers
 * count from the first sample. The policy is the live compensator's default (extrapolate). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gyrocal_coeffs.h"

#define MAX_FIELDS 16
#define START_UTIME 1000000000000000LL

static int split(char *line, char **fields) {
    int n = 0;
    char *p = line;
    fields[n++] = p;
    for (; *p && *p != '\n' && *p != '\r'; ++p) {
        if (*p == ',' && n < MAX_FIELDS) {
            *p = '\0';
            fields[n++] = p + 1;
        }
    }
    *p = '\0';
    return n;
}

static int column(char **names, int n, const char *name) {
    int i;
    for (i = 0; i < n; ++i)
        if (strcmp(names[i], name) == 0) return i;
    return -1;
}

static double number(char **f, int n, int col) {
    if (col < 0 || col >= n || f[col][0] == '\0') return NAN;
    return strtod(f[col], 0);
}

int main(int argc, char **argv) {
    static char header[4096], line[4096];
    char *names[MAX_FIELDS], *f[MAX_FIELDS];
    int nh, c_time, c_gyro, c_temp, c_supply, c_power;
    long not_computable = 0;
    gyrocal_compensator_t comp;
    FILE *in;
    if (argc != 2 || !(in = fopen(argv[1], "r"))) {
        fprintf(stderr, "usage: %s SAMPLES.csv (a readable file)\n", argv[0]);
        return 1;
    }
    if (!fgets(header, sizeof header, in)) return 1;
    nh = split(header, names);
    c_time = column(names, nh, "time_s");
    c_gyro = column(names, nh, "gyro_v");
    c_temp = column(names, nh, "temp_c");
    c_supply = column(names, nh, "supply_v");
    c_power = column(names, nh, "time_since_power_s");
    if (c_time < 0 || c_gyro < 0 || c_temp < 0) {
        fprintf(stderr, "%s: header lacks time_s, gyro_v or temp_c\n", argv[1]);
        return 1;
    }
    GYROCAL_TEST_INIT(&comp, GYROCAL_EXTRAPOLATE);
    printf("time_s,rate_dps,angle_deg\n");
    while (fgets(line, sizeof line, in)) {
        const int n = split(line, f);
        const double time_s = number(f, n, c_time), tsp = number(f, n, c_power);
        const long long utime = START_UTIME + llround(time_s * 1e6);
        gyrocal_rate_t r;
        if (isfinite(tsp)) {
            const long long on = utime - llround(tsp * 1e6);
            if (!comp.tracker.has_power_on || comp.tracker.power_on_utime != on)
                gyrocal_tracker_power_on(&comp.tracker, on);
        }
        if (gyrocal_compensate(&comp, utime, number(f, n, c_gyro), number(f, n, c_temp),
                               number(f, n, c_supply), &r))
            printf("%s,%.17g,%.17g\n", f[c_time], r.rate_dps, r.angle_deg);
        else
            ++not_computable;
    }
    printf("not_computable,%ld\n", not_computable);
    fclose(in);
    return 0;
}
