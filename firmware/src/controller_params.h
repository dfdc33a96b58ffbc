/*
 * controller_params.h - what controller.c takes from controller_params.c
 * (the library's own, not a public header).
 */
#ifndef FC_CONTROLLER_PARAMS_H
#define FC_CONTROLLER_PARAMS_H

#include "fc/controller.h"

/* The outer group's step, dt_s outer_divider times (by additions, so that
 * the defaults and init's check form the same value in both backends). */
fc_real fc_controller_outer_step_s(const fc_controller_params *p);

/* FC_INIT_OK when the modules' parameters agree: one step, one g, one
 * nominal mass, a maximum thrust between 1.5 x the weight and the rotors'. */
fc_init_result fc_controller_params_agree(const fc_controller_params *p);

#endif /* FC_CONTROLLER_PARAMS_H */
