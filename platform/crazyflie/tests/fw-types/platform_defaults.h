/* platform_defaults.h - the platform constants the glue reads, the values
 * of the firmware's platform_defaults_cf2.h (2.1+ propellers) and
 * platform_defaults_cf21bl.h. */
#ifndef CF_TEST_PLATFORM_DEFAULTS_H
#define CF_TEST_PLATFORM_DEFAULTS_H

#include "autoconf.h"

#if defined(CONFIG_PLATFORM_CF21BL)
#define ARM_LENGTH 0.050f
#define CF_MASS 0.0393f
#define THRUST_MIN 0.02136263065537499f
#define THRUST_MAX 0.2f
#define THRUST2TORQUE 0.00569278844371417f
#else
#define ARM_LENGTH 0.046f
#define CF_MASS 0.029f
#define THRUST_MIN 0.012817578393224994f
#define THRUST_MAX 0.12f
#define THRUST2TORQUE 0.0069928948992470565f
#endif

#endif
