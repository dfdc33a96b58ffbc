/*
 * robustness.h - when a simulated flight has diverged: the test behind the
 * Monte-Carlo summary's count of diverged runs (issue 9: "no run diverges").
 *
 * A run has diverged when any of these holds (the bounds are [montecarlo]
 * keys, scenario.h):
 *   - an output of the flight software held a NaN or an infinity (nan_outputs > 0);
 *   - the plant's state was not finite at some step;
 *   - after the transient, |z - z_r| exceeded diverged_error_m (max_abs_error_m);
 *   - the horizontal distance from the setpoint exceeded diverged_position_m;
 *   - the tilt exceeded diverged_tilt_deg (60 deg by default).
 */
#ifndef SIM_ROBUSTNESS_H
#define SIM_ROBUSTNESS_H

#include <stddef.h>

#include "scenario.h"
#include "sim.h"

enum {
    SIM_DIVERGED_NAN_OUTPUT = 1u << 0,
    SIM_DIVERGED_STATE = 1u << 1,
    SIM_DIVERGED_ERROR = 1u << 2,
    SIM_DIVERGED_POSITION = 1u << 3,
    SIM_DIVERGED_TILT = 1u << 4,
};
#define SIM_DIVERGED_REASON_COUNT 5

/* The reasons (a mask of SIM_DIVERGED_*) why the run with metrics m has
 * diverged; 0 if it has not. */
unsigned sim_divergence(const sim_metrics *m, const montecarlo_params *mc);

/* The name of reason bit i ("nan_output", "state", "error", "position", "tilt"). */
const char *sim_divergence_reason_name(int i);

/* The reasons as "tilt+error" (or "-" for none) in buf. */
void sim_divergence_text(unsigned reasons, char *buf, size_t len);

#endif /* SIM_ROBUSTNESS_H */
