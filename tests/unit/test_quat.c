#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>
#include "fc/quat.h"

static void test_smoke(void **state)
{
    (void)state;
    fc_arith ar = {0};
    float s = fc_to_float(fc_sin(&ar, fc_from_float(0.5f, FC_ANGLE_FRAC)), FC_UNIT_FRAC);
    assert_true(fabsf(s - sinf(0.5f)) < 1e-6f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_smoke)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
