/* range.h - the rangers' last readings (mm), defined by the test. */
#ifndef CF_TEST_RANGE_H
#define CF_TEST_RANGE_H

typedef enum { rangeFront = 0, rangeBack, rangeLeft, rangeRight, rangeUp, rangeDown, RANGE_T_END } rangeDirection_t;

float rangeGet(rangeDirection_t direction);

#endif
