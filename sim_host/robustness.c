/* robustness.c - the divergence test of a run (robustness.h). */
#include "robustness.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const reason_names[SIM_DIVERGED_REASON_COUNT] = {"nan_output", "state", "error", "position",
                                                                    "tilt"};

unsigned sim_divergence(const sim_metrics *m, const montecarlo_params *mc)
{
    unsigned reasons = 0u;
    if (m->nan_outputs > 0.0) {
        reasons |= SIM_DIVERGED_NAN_OUTPUT;
    }
    if (m->nonfinite_state_steps > 0.0 || !isfinite(m->max_position_error_m) || isnan(m->max_tilt_deg)) {
        reasons |= SIM_DIVERGED_STATE;
    }
    /* NaN max_abs_error_m: no error window (nothing to test) */
    if (m->max_abs_error_m > mc->diverged_error_m) {
        reasons |= SIM_DIVERGED_ERROR;
    }
    /* like the altitude error, judged once the transient is over: an excursion
     * that comes back (a heavy start trimmed by the integrals) is not a
     * divergence; max_position_error_m keeps the whole run's */
    if (m->settled_position_error_m > mc->diverged_position_m) {
        reasons |= SIM_DIVERGED_POSITION;
    }
    if (m->max_tilt_deg > mc->diverged_tilt_deg) {
        reasons |= SIM_DIVERGED_TILT;
    }
    return reasons;
}

const char *sim_divergence_reason_name(int i)
{
    return i >= 0 && i < SIM_DIVERGED_REASON_COUNT ? reason_names[i] : "?";
}

void sim_divergence_text(unsigned reasons, char *buf, size_t len)
{
    if (len == 0) {
        return;
    }
    buf[0] = '\0';
    if (reasons == 0u) {
        snprintf(buf, len, "-");
        return;
    }
    size_t used = 0;
    for (int i = 0; i < SIM_DIVERGED_REASON_COUNT; i++) {
        if ((reasons & (1u << i)) != 0u && used < len) {
            const int n = snprintf(buf + used, len - used, "%s%s", used > 0 ? "+" : "", reason_names[i]);
            used += n > 0 ? (size_t)n : 0u;
        }
    }
}
