/*
 * fc_library.c - the library's amalgamation: every source as one translation
 * unit, for the Cortex-M4F builds (the cf2 presets, firmware/CMakeLists.txt,
 * and the Crazyflie app's Kbuild, platform/crazyflie/fclib/Kbuild).
 *
 * Built from its sources one by one, each module's step is a call from
 * fc_controller_step, with the inputs and outputs passed through memory and
 * every small vec3/quat helper a call of its own. In one unit the compiler
 * can inline them into the step (with the inliner's limits raised where this
 * file is built), which takes about a quarter of the step's cycles away on
 * the M4F (tools/bench.sh). The sources stay the definition; this file only
 * includes each of them, in the order of firmware/CMakeLists.txt, which
 * checks at configure time that none is missing. Their file-local names are
 * unique across the library, so they do not clash here.
 *
 * Not for the ATmega: there flash, not speed of calls, is the limit.
 */
#include "../src/scalar.c"
#include "../src/vec3.c"
#include "../src/quat.c"
#include "../src/mat.c"
#include "../src/attitude_estimator.c"
#include "../src/attitude_heading.c"
#include "../src/attitude_control.c"
#include "../src/allocation.c"
#include "../src/altitude_reference.c"
#include "../src/altitude_control.c"
#include "../src/controller.c"
#include "../src/controller_params.c"
#include "../src/descent_shaping.c"
#include "../src/trajectory_tracking.c"
#include "../src/position_control.c"
#include "../src/pad_motion.c"
#include "../src/landing.c"
#include "../src/input_gate.c"
#include "../src/vertical_estimator.c"
#include "../src/land_detector.c"
#include "../src/failsafe.c"
