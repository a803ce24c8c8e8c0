/* gyrocal's model path in C99: the ONE definition of the model inputs (trackers with their
 * state), the term values, the evaluation and the compensation of one sample.
 *
 * This file is compiled into gyrocal's C++ libraries (the fitter, the analysis, the live
 * compensator and `gyrocal compensate` all evaluate through it) and is copied verbatim into the
 * firmware header that `gyrocal export --format c-header` writes, so that the same samples give
 * the same rate everywhere, bit for bit where the arithmetic is the same (IEEE double, no fused
 * multiply-add, no -ffast-math).
 *
 * Model: y = sum_i coeffs[i] * term_i(inputs), dT = temp_c - t0_c.
 *
 * Inputs and their state (gyrocal_tracker_t), each updated once per sample in time order from
 * the unit's power-on (or from the first sample when no power-on time is known):
 *   dtemp_dt_c_per_s  dT/dt by the difference of two exponential averages of temp_c with time
 *                     constants tau and 2 tau: on a steady ramp of rate r each average lags by
 *                     r times its time constant, so (fast - slow) / tau = r exactly; white
 *                     temperature noise is averaged over ~tau. Discrete form: alpha =
 *                     dt / (tau + dt), which keeps the ramp lag exactly tau at any sample period.
 *                     It starts at 0 on the first sample (the unit is assumed at rest) and
 *                     settles within a few 2 tau.
 *   branch            heating/cooling branch by a play operator of width w on temp_c: a memory
 *                     that follows the temperature at a distance of at most w/2; branch =
 *                     (temp_c - memory) / (w/2), in [-1, 1]: +1 after a rise of w from the last
 *                     turning point, -1 after a fall of w, a linear transition in between. It
 *                     starts at 0 (branch unknown at power-on). `heating` is the sign-only form:
 *                     the side the branch last reached (+1 / -1), 0 before either.
 *   time_since_power_s  utime minus the power-on time; the power-on time is given
 *                     (gyrocal_tracker_power_on) or, failing that, the first sample's time
 *                     (power_on_assumed is then set, for the caller to say so).
 *   supply_v          the sample's measured supply (NAN when not measured).
 *   direction         sign of (gyro_v - offset_v) at evaluation: for a direction-dependent
 *                     scale factor.
 * A term whose input is unknown, or was tracked with another time constant or width than the
 * term names, evaluates to NAN, so a model never silently uses the wrong input.
 */
#ifndef GYROCAL_MODEL_H
#define GYROCAL_MODEL_H

#include <math.h>
#include <stdint.h>

#define GYROCAL_NOMINAL_SUPPLY_V 5.0    /* [V] supply terms are taken about this */
#define GYROCAL_DEFAULT_RATE_TAU_S 5.0  /* [s] time constant of "dTdt" without a parameter */
#define GYROCAL_SIGN_BRANCH_WIDTH_C 1.0 /* [degC] play-operator width of "heating" */

#define GYROCAL_CLIP 0        /* temp_c clipped to [temp_min_c, temp_max_c] */
#define GYROCAL_EXTRAPOLATE 1 /* the polynomial used outside the range the fit saw */

#define GYROCAL_IN_RANGE 0 /* range flags (rate_t.range_flag) */
#define GYROCAL_CLIPPED 1
#define GYROCAL_EXTRAPOLATED 2

typedef struct {
    double temp_c;             /* [degC] sensor temperature */
    double dtemp_dt_c_per_s;   /* [degC/s] see above */
    double rate_tau_s;         /* [s] time constant dtemp_dt_c_per_s was tracked with */
    double supply_v;           /* [V] measured supply, NAN when not measured */
    double branch;             /* [1] play-operator branch in [-1, 1] */
    double heating;            /* [1] +1 / -1 side last reached, 0 before either */
    double branch_width_c;     /* [degC] play-operator width the two above were tracked with */
    double direction;          /* [1] +1 / -1 rotation direction */
    double time_since_power_s; /* [s] since the unit was powered */
} gyrocal_inputs_t;

/* Inputs all unknown (NAN). */
static inline gyrocal_inputs_t gyrocal_inputs_unknown(void) {
    gyrocal_inputs_t in;
    in.temp_c = NAN;
    in.dtemp_dt_c_per_s = NAN;
    in.rate_tau_s = NAN;
    in.supply_v = NAN;
    in.branch = NAN;
    in.heating = NAN;
    in.branch_width_c = NAN;
    in.direction = NAN;
    in.time_since_power_s = NAN;
    return in;
}

/* Term kinds (gyrocal's term registry); dT = temp_c - t0_c. */
enum {
    GYROCAL_TERM_UNKNOWN = -1, /* a name this code does not know: evaluates to NAN */
    GYROCAL_TERM_ONE = 0,      /* "1"            1 */
    GYROCAL_TERM_DT,           /* "dT"           dT [degC] */
    GYROCAL_TERM_DT2,          /* "dT^2"         dT^2 [degC^2] */
    GYROCAL_TERM_DT3,          /* "dT^3"         dT^3 [degC^3] */
    GYROCAL_TERM_DTDT,         /* "dTdt", "dTdt(tau)"  dtemp_dt_c_per_s [degC/s] */
    GYROCAL_TERM_HEATING,      /* "heating"      sign-only branch, width 1 degC */
    GYROCAL_TERM_BRANCH,       /* "heating(w)"   play-operator branch of width w [degC] */
    GYROCAL_TERM_SUPPLY,       /* "supply"       supply_v - GYROCAL_NOMINAL_SUPPLY_V [V] */
    GYROCAL_TERM_DIRECTION,    /* "direction"    sign(direction) */
    GYROCAL_TERM_WARMUP,       /* "warmup(tau)"  exp(-time_since_power_s / tau) */
    GYROCAL_TERM_KNOT_ABOVE,   /* "knot_above(k)"  max(0, dT - k)^3 [degC^3] */
    GYROCAL_TERM_KNOT_BELOW,   /* "knot_below(k)"  max(0, k - dT)^3 [degC^3] */
    GYROCAL_TERM_DT_DTDT       /* "dT*dTdt", "dT*dTdt(tau)"  dT x dtemp_dt_c_per_s [degC^2/s] */
};
/* Kinds are stored by number in exported firmware headers: a new kind is appended, never
 * inserted. A firmware built from an older copy of this file reaches `default` for a kind it
 * does not know and evaluates it to NAN (the rate is then not computable, never wrong). */

typedef struct {
    int kind;     /* GYROCAL_TERM_* */
    double param; /* dTdt, dT*dTdt: tau [s] (0 = default); heating(w): w [degC]; warmup: tau [s];
                     knot_above / knot_below: the knot k [degC] relative to t0_c (any sign) */
} gyrocal_term_t;

static inline double gyrocal_sign(double v) {
    if (!isfinite(v)) return NAN;
    return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
}

static inline double gyrocal_term_value(const gyrocal_term_t *t, double dT,
                                        const gyrocal_inputs_t *in) {
    switch (t->kind) {
        case GYROCAL_TERM_ONE:
            return 1.0;
        case GYROCAL_TERM_DT:
            return dT;
        case GYROCAL_TERM_DT2:
            return dT * dT;
        case GYROCAL_TERM_DT3:
            return dT * dT * dT;
        case GYROCAL_TERM_DTDT: {
            const double tau = t->param > 0.0 ? t->param : GYROCAL_DEFAULT_RATE_TAU_S;
            return in->rate_tau_s == tau ? in->dtemp_dt_c_per_s : NAN;
        }
        case GYROCAL_TERM_DT_DTDT: {
            /* a thermometer lagging the die by L reads T - L dT/dt on a ramp, so a static offset
             * f(T) leaves f'(T) L dT/dt = (o1 + 2 o2 dT) L dT/dt: dTdt takes o1 L, this term the
             * product's 2 o2 L. dT is the (clipped) dT of the polynomial terms. */
            const double tau = t->param > 0.0 ? t->param : GYROCAL_DEFAULT_RATE_TAU_S;
            return in->rate_tau_s == tau ? dT * in->dtemp_dt_c_per_s : NAN;
        }
        case GYROCAL_TERM_HEATING:
            return in->branch_width_c == GYROCAL_SIGN_BRANCH_WIDTH_C ? gyrocal_sign(in->heating)
                                                                     : NAN;
        case GYROCAL_TERM_BRANCH:
            return in->branch_width_c == t->param ? in->branch : NAN;
        case GYROCAL_TERM_SUPPLY:
            return in->supply_v - GYROCAL_NOMINAL_SUPPLY_V;
        case GYROCAL_TERM_DIRECTION:
            return gyrocal_sign(in->direction);
        case GYROCAL_TERM_WARMUP:
            return exp(-in->time_since_power_s / t->param);
        case GYROCAL_TERM_KNOT_ABOVE: {
            /* one knot of a cubic spline in temperature: zero (with its first two derivatives)
             * at the knot and on one side of it; a static shape beyond the cubic, e.g. a bend
             * at one end of the range */
            const double u = dT > t->param ? dT - t->param : 0.0;
            return u * u * u;
        }
        case GYROCAL_TERM_KNOT_BELOW: {
            const double u = dT < t->param ? t->param - dT : 0.0;
            return u * u * u;
        }
        default:
            return NAN;
    }
}

typedef struct {
    int num_terms;
    const char *const *term_names; /* gyrocal's names, e.g. "1", "dT^2", "warmup(600)" */
    const gyrocal_term_t *terms;   /* how each is computed */
    const double *coeffs;          /* [unit of y / unit of term] */
    double t0_c;                   /* [degC] reference temperature of dT */
    double temp_min_c;             /* [degC] valid range: what the fit saw */
    double temp_max_c;             /* [degC] */
} gyrocal_model_t;

/* y = sum_i coeffs[i] * term_i, summed in term order; polynomial terms from temp_c (clipped or
 * not, per policy), the others from the inputs. NAN when temp_c is not finite. range_flag (may
 * be NULL) receives GYROCAL_IN_RANGE, GYROCAL_CLIPPED or GYROCAL_EXTRAPOLATED. */
static inline double gyrocal_eval_policy(const gyrocal_model_t *m, const gyrocal_inputs_t *in,
                                         int policy, int *range_flag) {
    double t = in->temp_c, dT, y = 0.0;
    int i, flag = GYROCAL_IN_RANGE;
    if (!isfinite(t)) {
        if (range_flag) *range_flag = flag;
        return NAN;
    }
    if (t < m->temp_min_c || t > m->temp_max_c) {
        if (policy == GYROCAL_CLIP) {
            t = t < m->temp_min_c ? m->temp_min_c : m->temp_max_c;
            flag = GYROCAL_CLIPPED;
        } else {
            flag = GYROCAL_EXTRAPOLATED;
        }
    }
    dT = t - m->t0_c;
    for (i = 0; i < m->num_terms; ++i) y += m->coeffs[i] * gyrocal_term_value(&m->terms[i], dT, in);
    if (range_flag) *range_flag = flag;
    return y;
}

/* The firmware default: temp_c clipped to the valid range. */
static inline double gyrocal_eval(const gyrocal_model_t *m, const gyrocal_inputs_t *in) {
    return gyrocal_eval_policy(m, in, GYROCAL_CLIP, 0);
}

/* ---- Input trackers ---------------------------------------------------------------------- */

typedef struct {
    double rate_tau_s;     /* [s] dT/dt time constant (> 0) */
    double branch_width_c; /* [degC] play-operator width (> 0) */
} gyrocal_tracker_config_t;

static inline gyrocal_tracker_config_t gyrocal_tracker_config_default(void) {
    gyrocal_tracker_config_t c;
    c.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    c.branch_width_c = GYROCAL_SIGN_BRANCH_WIDTH_C;
    return c;
}

typedef struct {
    gyrocal_tracker_config_t config;
    int started;            /* a sample has been seen */
    int64_t last_utime;     /* [us] newest sample */
    double fast_c, slow_c;  /* [degC] averages of temp_c over tau and 2 tau */
    double rate_c_per_s;    /* [degC/s] newest dT/dt */
    double memory_c;        /* [degC] play-operator memory */
    double branch, heating; /* [1] newest branch outputs */
    int has_power_on;       /* power_on_utime is set */
    int power_on_assumed;   /* power_on_utime is the first sample's (not a power-on record) */
    int64_t power_on_utime; /* [us] */
} gyrocal_tracker_t;

static inline void gyrocal_tracker_init(gyrocal_tracker_t *t, gyrocal_tracker_config_t config) {
    t->config = config;
    t->started = 0;
    t->last_utime = 0;
    t->fast_c = t->slow_c = 0.0;
    t->rate_c_per_s = NAN;
    t->memory_c = 0.0;
    t->branch = t->heating = NAN;
    t->has_power_on = 0;
    t->power_on_assumed = 0;
    t->power_on_utime = 0;
}

/* The unit was powered at power_on_utime [us] (a new value is a new power cycle). */
static inline void gyrocal_tracker_power_on(gyrocal_tracker_t *t, int64_t power_on_utime) {
    t->has_power_on = 1;
    t->power_on_assumed = 0;
    t->power_on_utime = power_on_utime;
}

/* One sample, in time order (a sample not after the previous one, or a non-finite temp_c,
 * leaves the state as it was). Fills *out with the inputs at this sample; direction is NAN (set
 * by the evaluation). */
static inline void gyrocal_tracker_update(gyrocal_tracker_t *t, int64_t utime, double temp_c,
                                          double supply_v, gyrocal_inputs_t *out) {
    const double tau = t->config.rate_tau_s, half = 0.5 * t->config.branch_width_c;
    if (!t->has_power_on) {
        t->has_power_on = 1;
        t->power_on_assumed = 1;
        t->power_on_utime = utime;
    }
    if (isfinite(temp_c) && (!t->started || utime > t->last_utime)) {
        if (!t->started) {
            t->fast_c = t->slow_c = temp_c;
            t->rate_c_per_s = 0.0;
            t->memory_c = temp_c;
            t->branch = t->heating = 0.0;
            t->started = 1;
        } else {
            const double dt_s = 1e-6 * (double)(utime - t->last_utime);
            t->fast_c += dt_s / (tau + dt_s) * (temp_c - t->fast_c);
            t->slow_c += dt_s / (2.0 * tau + dt_s) * (temp_c - t->slow_c);
            t->rate_c_per_s = (t->fast_c - t->slow_c) / tau;
            if (temp_c > t->memory_c + half) t->memory_c = temp_c - half;
            if (temp_c < t->memory_c - half) t->memory_c = temp_c + half;
            t->branch = (temp_c - t->memory_c) / half;
            if (t->branch >= 1.0) t->heating = 1.0;
            if (t->branch <= -1.0) t->heating = -1.0;
        }
        t->last_utime = utime;
    }
    out->temp_c = temp_c;
    out->dtemp_dt_c_per_s = t->rate_c_per_s;
    out->rate_tau_s = tau;
    out->supply_v = supply_v;
    out->branch = t->branch;
    out->heating = t->heating;
    out->branch_width_c = t->config.branch_width_c;
    out->direction = NAN;
    out->time_since_power_s = 1e-6 * (double)(utime - t->power_on_utime);
}

/* ---- Compensation of one sample ---------------------------------------------------------- */

typedef struct {
    const gyrocal_model_t *offset;      /* offset_v [V] */
    const gyrocal_model_t *sensitivity; /* sensitivity_v_per_dps [V/(deg/s)] */
    int policy;                         /* GYROCAL_CLIP or GYROCAL_EXTRAPOLATE */
    gyrocal_tracker_t tracker;
    int integrating;      /* angle_deg holds an integral */
    int64_t last_utime;   /* [us] newest compensated sample */
    double last_rate_dps; /* [deg/s] */
    double angle_deg;     /* [deg] trapezoid integral of rate_dps since it began */
} gyrocal_compensator_t;

typedef struct {
    gyrocal_inputs_t inputs; /* what the models were evaluated with */
    double offset_v;         /* [V] */
    double sensitivity_v_per_dps;
    double rate_dps;  /* [deg/s] NAN when not computable */
    double angle_deg; /* [deg] */
    int range_flag;   /* GYROCAL_IN_RANGE / _CLIPPED / _EXTRAPOLATED (the worse of both) */
} gyrocal_rate_t;

static inline void gyrocal_compensator_init(gyrocal_compensator_t *c, const gyrocal_model_t *offset,
                                            const gyrocal_model_t *sensitivity, int policy,
                                            gyrocal_tracker_config_t config) {
    c->offset = offset;
    c->sensitivity = sensitivity;
    c->policy = policy;
    gyrocal_tracker_init(&c->tracker, config);
    c->integrating = 0;
    c->last_utime = 0;
    c->last_rate_dps = 0.0;
    c->angle_deg = 0.0;
}

/* Evaluates both models at inputs already tracked: rate_dps = (gyro_v - offset_v) /
 * sensitivity_v_per_dps, direction = sign(gyro_v - offset_v). Does not touch the angle. */
static inline void gyrocal_rate_at(const gyrocal_compensator_t *c, double gyro_v,
                                   gyrocal_rate_t *r) {
    int f_off = 0, f_sens = 0;
    r->offset_v = gyrocal_eval_policy(c->offset, &r->inputs, c->policy, &f_off);
    r->inputs.direction = gyro_v - r->offset_v >= 0.0 ? 1.0 : -1.0;
    r->sensitivity_v_per_dps = gyrocal_eval_policy(c->sensitivity, &r->inputs, c->policy, &f_sens);
    r->rate_dps = (gyro_v - r->offset_v) / r->sensitivity_v_per_dps;
    r->range_flag = f_off != GYROCAL_IN_RANGE ? f_off : f_sens;
}

/* One raw sample in time order: tracks the inputs, evaluates, integrates the angle. Returns 1
 * with *r filled, or 0 when the rate is not computable (a model needs an input this stream does
 * not have, e.g. supply_v NAN for a supply term); the angle then restarts after the hole. */
static inline int gyrocal_compensate(gyrocal_compensator_t *c, int64_t utime, double gyro_v,
                                     double temp_c, double supply_v, gyrocal_rate_t *r) {
    gyrocal_tracker_update(&c->tracker, utime, temp_c, supply_v, &r->inputs);
    gyrocal_rate_at(c, gyro_v, r);
    if (!isfinite(r->rate_dps)) {
        c->integrating = 0;
        r->angle_deg = c->angle_deg;
        return 0;
    }
    if (c->integrating)
        c->angle_deg +=
            0.5 * (c->last_rate_dps + r->rate_dps) * 1e-6 * (double)(utime - c->last_utime);
    c->integrating = 1;
    c->last_rate_dps = r->rate_dps;
    c->last_utime = utime;
    r->angle_deg = c->angle_deg;
    return 1;
}

#endif /* GYROCAL_MODEL_H */
