/*
 * fc/altitude_control.h - the altitude law: Smooth Sliding Control (SSC) in
 * the forms of the dissertation's chapter 4, and baselines with the same
 * interface to compare against.
 *
 * Plant (3.4):  z'' = u / Theta* - g,   Theta* = m / (k_h k_g),  u the vertical force.
 * Tracking error (4.1) e = z - z_r; ideal sliding variable sigma = e' + l0 e (4.2).
 *
 * SSC (Figure 4.1):
 *   sigma_tilde = sigma_hat - sigma_bar                        (4.4)
 *   sigma_bar'  = -a_m sigma_bar + kappa_m (u0 - u0_av)        (4.5)  prediction-error loop
 *   u           = u_nom - u0_av                                (4.6)
 *   tau_av u0_av' = -u0_av + u0                                (4.7)  averaging filter
 *   u0          = rho sgn(sigma_tilde)                         (4.8)  relay
 *   relative degree one (z' measured):   sigma_hat = sigma
 *   relative degree two (z' not measured): sigma_hat = (s + l0)/(tau_f s + 1) e, realised
 *       by (4.18): tau_f x_f' = -x_f + e,  sigma_hat = (e - (1 - tau_f l0) x_f) / tau_f
 * Modulation rho:
 *   CONSTANT        rho fixed (the dissertation's simulation: rho = 50)
 *   NORM_OBSERVER   (4.40)-(4.43): tau_av w5' = -(kp_min/kappa_m) w5 + w4,
 *                   rho = c_eta w5 + w4 + |w4[k] - w4[k-1]| + delta + k0 |sigma_tilde|.
 *                   The bounds are the tight forms of (4.38) and (4.42), computed from
 *                   the parameters at init: the dissertation's triangle inequalities add
 *                   terms that cancel (u_nom ~ Theta phi against phi), which made rho
 *                   about four times the disturbance it bounds.
 *                   - w4 = (w3 + a_m |sigma|)/kappa_m with w3 = max |kp u_nom - phi| over
 *                     kp in [kp_min, kp_max]: kp U_d = kp u_nom - phi is linear in kp, so
 *                     the largest magnitude is at an end (the dissertation: kp_max |u_nom| + |phi|).
 *                   - d_eq2 (4.37) = -(1 - kp/kappa_m) eta1 - (kp U_d + a_m sigma)/kappa_m, so
 *                     |d_eq2| <= c_eta w5 + w4 with c_eta = max |1 - kp/kappa_m| over the kp
 *                     range (the dissertation: 1 + kp_max/kappa_m).
 *                   - the term the discretisation adds: the relay is held over the step
 *                     while d_eq2 moves on; w4 is the part of the bound that moves within
 *                     a step (w5 is a lag of tau_av kappa_m/kp_min), and its change over the
 *                     last step, |w4[k] - w4[k-1]|, bounds its change over the next one for
 *                     signals smooth at the step (modulo vanishing terms, as (4.34)).
 *                   relative degree two: the eta norm observer of 4.3.2 instead:
 *                   d_eq3 = eta1 + eta2/kappa_m + a_m eta3/kappa_m (4.81) is the output of
 *                   the eta-dynamics tau_bar eta' = A_eta eta + B_eta kp D driven by
 *                   kp D = kp u_nom - psi, psi = g + z_r'' + l0^2 e. From (4.67)-(4.69) its
 *                   transfer function is
 *                     H(s) = (tau_av s^2 + (1 + a_m tau_av) s + a_m)
 *                            / (tau_bar s^3 + (1 - l0 tau_f) tau_av kappa_m s^2
 *                               + (kp - l0 tau_av kappa_m) s + kp a_m),
 *                   H(0) = 1/kp, h(0+) = 1/(tau_f kappa_m). In the time scale of the lead
 *                   filter, x = tau_f s, h(t) = g(t/tau_f)/(tau_f kappa_m) with g the impulse
 *                   response of M(x)/P(x), both monic:
 *                     P(x) = x^3 + c2 x^2 + c1 x + c0,  c2 = 1 - l0 tau_f,
 *                            c1 = (kp - l0 tau_av kappa_m) q, c0 = kp a_m tau_f q,
 *                            q = tau_f/(tau_av kappa_m),
 *                     M(x) = x^2 + m1 x + m0,  m1 = (1 + a_m tau_av) tau_f/tau_av,
 *                            m0 = a_m tau_f^2/tau_av.
 *                   Computed at init for each kp of a grid over [kp_min, kp_max]: the real
 *                   root r of P (Newton from the left of every root) and its residue
 *                   rho_f = M(r)/P'(r), the fast term; the rest of g, g - rho_f e^(r x), is
 *                   the pair of P(x)/(x - r) = x^2 + b1 x + b0, with value A = 1 - rho_f and
 *                   slope g'(0) - rho_f r = m1 - c2 - rho_f r at 0; as a damped oscillation
 *                   e^(-s t)(A cos(w t) + B sin(w t)) it is majorised by sqrt(A^2 + B^2) e^(-s t),
 *                   otherwise (overdamped or w < s/2) by (|A| + 2 |C|/(e s')) e^(-s' t/2),
 *                   s' the slower real part, C = slope + s A (t e^(-s' t/2) <= 2/(e s')).
 *                   So |h(t)| <= c_f e^(-l_f t) + c_s e^(-l_s t), the tightest pair of
 *                   exponentials of this form, exact at t = 0 (c_f + c_s >= h(0)).
 *                   The kp range is cut into FC_ALT_ETA_CELLS cells; on each, the majorant
 *                   takes the larger c and the smaller l of its two ends, and |kp D| <= the
 *                   larger of |kp_j u_nom - psi| at the ends (kp D is linear in kp). This
 *                   keeps apart what the dissertation's bound couples: h is largest at
 *                   kp_min, |kp D| at kp_max (u_nom ~ Theta0 psi makes kp D vanish near
 *                   1/Theta0), and their product is bounded cell by cell. Lemma 11 on each
 *                   term: w' = -l w + v, v the cell's input bound, and
 *                   rho_bar = max over cells of (c_f w_f + c_s w_s).
 *                   The terms the discretisation adds: the relay is held over the step ahead
 *                   while d_eq3 moves on. (1) kp D moves within the step: its change over the
 *                   last step, |kp_j D[k] - kp_j D[k-1]| at the ends, bounds its change over the
 *                   next one for signals smooth at the step, so v = max |kp_j D| + max |delta
 *                   kp_j D| bounds |kp D| over the whole step ahead; (2) a state w between
 *                   samples lies between w[k] and w[k+1] (first order, input held), so
 *                   rho_bar uses max(w[k], w[k+1]) of each: the bound holds at every instant
 *                   of the step, not only at its samples.
 *                   Relative degree two also needs the eta-dynamics minimum phase over
 *                   the kp range (Remark 9): tau_f l0 < 1, tau_av kappa_m l0 < kp_min and
 *                   tau_av kappa_m l0 (1 - tau_f l0) + tau_f kp_min (a_m + l0) < kp_min;
 *                   init rejects a tuning that breaks them, and, with the eta norm
 *                   observer, one whose c1 or c0 exceeds 3 over the kp range (the roots
 *                   then stay inside [-4, 0), what RATIO holds through the cubic) or whose
 *                   root finding does not settle. The majorant's constants are taken at
 *                   the cells' ends: that they cover h for every kp inside a cell is not
 *                   proven but checked (tests/unit/test_altitude_control.c samples kp
 *                   across the range for two tunings).
 *   EXTRA           (4.54)-(4.56): rho = c_eta |u0_av| + w4 + delta (c_eta, w4 as above)
 * Nominal control (4.4): u_nom = Theta phi, phi = g + z_r'' - l0 e'. The start of (3.6)
 * asks for z_r'' = z_r_init/tau_zr^2 and z_r' = -z_r_init/tau_zr, more than the thrust
 * gives: fed forward as it is, z_r'' holds the thrust at its maximum while the reference
 * drops away, and the vehicle then falls onto it faster than it can brake. So the z_r''
 * in phi is held inside what the thrust gives level for every Theta inside its bounds,
 * [thrust_min/Theta_min - g, thrust_max/Theta_max - g] (widened to hold 0), and u_nom
 * inside the vertical force the thrust delivers, [u_min, u_max]. Theta fixed at
 * Theta0, or adapted by (4.83) in the discrete form below, projected onto
 * [Theta_min, Theta_max] = [1/kp_max, 1/kp_min] (4.15).
 *
 * Adaptation in discrete time. With u = Theta phi - u0_av, (3.4) and (4.2) give
 *   Theta* sigma' = (Theta - Theta*) phi - u0_av,
 * and the dissertation's V = Theta* sigma^2/2 + (Theta - Theta*)^2/(2 gamma) has, under
 * (4.83), V' = -sigma u0_av: the adaptation is lossless, every bit of damping of the
 * pair (sigma, Theta) comes from the SSC's u0_av. The pair is an oscillator at
 * w_theta = |phi| sqrt(gamma/Theta*), about g sqrt(gamma/Theta*). At a fixed step two
 * things take that damping away: the explicit update (u_nom from the Theta before the
 * update) makes V grow by a factor of about 1 + (w_theta dt)^2 a step, and the discrete
 * relay has a quasi-sliding band (sigma_bar moves by about kappa_m rho dt a step) inside
 * which it chatters symmetrically, so u0_av carries nothing of the mode and cannot damp
 * it: a limit cycle whose size is the band's, twice as large at half the rate. The law:
 *   Theta_I <- proj(Theta_I - gamma dt sat(sigma phi)) first, frozen while clamped or held
 *   Theta    = proj(Theta_I - gamma_p [sigma phi]_lp)  this step's u_nom = Theta phi
 * with [.]_lp a first-order low-pass of time constant tau_p = 1/(4 w_theta) (w_theta at
 * Theta0 and phi = g), fed 0 while held (the proportional part fades out), and sat the
 * bound of the learning rate below:
 * - update order: u_nom is formed with the Theta_I just updated, the semi-implicit
 *   (symplectic) Euler step of the lossless pair, which keeps its energy instead of
 *   growing it;
 * - a proportional part (the PI adaptive law): with Theta_I in V,
 *   V' = -sigma u0_av - gamma_p phi^2 sigma^2 <= -sigma u0_av, so the dissertation's
 *   argument holds term by term with a damping that does not depend on the relay's
 *   band or on dt. gamma_p = 2 zeta sqrt(gamma Theta0)/g (zeta = FC_ALT_THETA_DAMPING)
 *   puts the mode's damping ratio at zeta for Theta* = Theta0 and phi = g, between
 *   zeta sqrt(Theta0/Theta_max) and zeta sqrt(Theta0/Theta_min) inside the bounds; its
 *   discrete factor gamma_p phi^2 dt/Theta* stays far below 1 at 250 Hz;
 * - projection of both onto [Theta_min, Theta_max]: V does not grow under it (Theta* is
 *   inside); Theta_I is what is learnt and what is frozen; gamma_p [sigma phi]_lp
 *   remembers sigma over tau_p only and learns nothing;
 * - the low-pass keeps one glitched sample of z or z' (SPEC "Plausibility") from
 *   reaching u_nom with the full gain gamma_p phi^2: it passes (1 - e^(-dt/tau_p)) of the
 *   jump; at the mode it lags by atan(1/4), so the damping is cos(atan(1/4)) of the above.
 * Bounded learning rate. (3.4) delivers u at once; the motors deliver it through
 * their lag tau_m, which with the measurement delay T takes about w_theta (tau_m + T)
 * of phase at the mode (30-50 degrees for 50 ms motors and 20-30 ms of delay at
 * w_theta ~ 11 rad/s): V' = -sigma u0_av no longer holds there, the lossless pair is
 * pumped, and Theta swings between its bounds in a limit cycle near w_theta. So the
 * integral learns from sigma phi bounded to +-FC_ALT_THETA_LEARN_SIGMA_PHI (about
 * 2 cm/s of sigma at phi = g): inside the bound (4.83) and V are unchanged; beyond it
 * the pumping gain falls with the amplitude, and V' gains at most
 * |Theta - Theta*| (|sigma phi| - bound), while the SSC alone keeps sigma_tilde at 0
 * for every Theta inside the projection's bounds (rho of (4.39) covers
 * |(Theta - Theta*) phi| over [Theta_min, Theta_max], (4.15)): boundedness does not
 * rest on the adaptation. The cost: Theta_I moves by at most gamma times the bound a
 * second (a quarter of Theta0 a second with the gains of 4.4). The bound also keeps a
 * reference step (the landing's press, fc/landing.h) from being learnt as a mass
 * change; once contact is planned (the touchdown window) the controller holds the
 * adaptation: Theta* becomes the pad's.
 * Lag schedule. With L = actuator_lag_s known at init, gamma and the damping ratio
 * zeta are both divided by d = 1 + w_theta L (w_theta = g sqrt(gamma/Theta0) of the
 * tuning given): the mode moves to w_theta/sqrt(d), and the proportional part, a
 * feedback of sigma through u_nom whose crossover is about 2 zeta w_theta, to
 * 2 zeta w_theta/d^(3/2): the phase L takes at either, the part of V' = -sigma u0_av
 * that the lag spoils, shrinks to w_theta L/sqrt(d) and below. (4.83) and V keep
 * their form with the smaller gamma; the price is a slower Theta (a mass step is
 * learnt over sqrt(d) times longer). L = 0 leaves the law as above.
 * The alternatives, against the same V: a normalised gradient gamma/(1 + mu phi^2) only
 * rescales gamma (phi stays near g) and moves w_theta, without damping; an implicit
 * gradient (sigma of the next step) damps by O(dt), less the faster the loop runs; a
 * dead zone as wide as the relay's band stops the cycle but freezes Theta wherever the
 * cycle left it; sigma-modification pulls Theta back to Theta0 (a bias of the order of
 * the payload change) and damps the mode only when it is large. The proportional part
 * passes sigma's noise into u_nom with the gain gamma_p phi^2.
 *
 * Anti-windup (part of the law): the thrust command is clamped to
 * [thrust_min, thrust_max]; while clamped the adaptation is frozen and the
 * averaging filter's state is held inside the band that the clamped actuator can
 * deliver, u0_av in [u_nom - u_max, u_nom - u_min], and inside what (4.7) makes of a
 * relay of amplitude rho, |u0_av| <= rho (the two bands overlap: u_nom is in [u_min, u_max]).
 *
 * Tilt compensation: the vertical force u is delivered by a body thrust
 * F = u / k_h with k_h = cos(roll) cos(pitch) from the measured attitude, bounded
 * below by tilt_cos_min.
 *
 * Discretisation at the fixed step dt, input held over the step (exact ZOH):
 *   u0_av    <- a u0_av + (1 - a) u0,                  a = e^(-dt/tau_av)
 *   sigma_bar<- b sigma_bar + kappa_m c (u0 - u0_av),  b = e^(-a_m dt),
 *               c = (a - b) / (a_m - 1/tau_av)  (the pair (sigma_bar, u0_av) is a
 *               triangular linear system driven by the held u0; c -> dt e^(-a_m dt)
 *               when a_m = 1/tau_av)
 *   w5       <- p w5 + (1 - p) (kappa_m / kp_min) w4,  p = e^(-kp_min dt/(kappa_m tau_av))
 *   x_f      <- f x_f + (1 - f) e,                     f = e^(-dt/tau_f)
 *   w_f, w_s <- e^(-l dt) w + ((1 - e^(-l dt))/l) v    each cell of the eta norm observer, v held
 *   Theta_I  <- Theta_I - gamma dt sigma phi           (integrator: Euler is its ZOH; before u_nom)
 * With a discrete relay the ideal sliding mode becomes a quasi-sliding band of
 * about rho dt / tau_av in u0_av: a modulation only as large as needed keeps
 * the control ripple small.
 *
 * Baselines (the same clamp and tilt compensation; in the sliding-mode ones u_nom = Theta0 phi
 * with z_r'' bounded as above):
 *   PID            the Crazyflie's structure: position PID -> velocity setpoint,
 *                  velocity PID -> thrust, with feed-forward of z_r' and z_r''.
 *                  Tuning rule: velocity loop kp_v = 2 zeta w_v Theta0, ki_v = w_v^2 Theta0 / 4,
 *                  position loop kp_z = w_v / 4 (a loop four times slower), ki_z = kp_z^2 / 8.
 *   SMC_SIGN       u = u_nom - k sgn(sigma), k = rho (the same disturbance bound).
 *   SMC_BOUNDARY   u = u_nom - k sat(sigma / phi_bl), phi_bl the boundary-layer width.
 *   SUPER_TWISTING u = u_nom - k1 |sigma|^(1/2) sgn(sigma) + v, v' = -k2 sgn(sigma);
 *                  Levant's rule k2 = 1.1 L Theta0, k1 = 1.5 sqrt(L) Theta0 with L a bound of the
 *                  disturbance's derivative in m/s^3.
 */
#ifndef FC_ALTITUDE_CONTROL_H
#define FC_ALTITUDE_CONTROL_H

#include "fc/altitude_reference.h"
#include "fc/scalar.h"
#include "fc/status.h"

/* sigma times phi, in m^2/s^3, for the adaptation law: [-32768, 32768), 1.5e-5 */
#define FC_SIGMA_PHI_FRAC 16

/* Damping ratio of the adaptive mode (sigma, Theta) with the proportional part
 * of the adaptation ("Adaptation in discrete time" above). */
#define FC_ALT_THETA_DAMPING 0.7f

/* |sigma phi| in m^2/s^3 the integral part of the adaptation learns from at most
 * ("Bounded learning rate" above): about 2 cm/s of sigma at phi = g. */
#define FC_ALT_THETA_LEARN_SIGMA_PHI 0.2f

/* Cells of the kp range on which the eta norm observer (relative degree two)
 * majorises the impulse response to d_eq3 (header comment, NORM_OBSERVER). */
#ifndef FC_ALT_ETA_CELLS
#define FC_ALT_ETA_CELLS 3
#endif

typedef enum fc_altitude_law {
    FC_ALT_LAW_SSC = 0,
    FC_ALT_LAW_PID,
    FC_ALT_LAW_SMC_SIGN,
    FC_ALT_LAW_SMC_BOUNDARY,
    FC_ALT_LAW_SUPER_TWISTING,
    FC_ALT_LAW_COUNT
} fc_altitude_law;

typedef enum fc_ssc_modulation {
    FC_SSC_MODULATION_CONSTANT = 0,
    FC_SSC_MODULATION_NORM_OBSERVER,
    FC_SSC_MODULATION_EXTRA
} fc_ssc_modulation;

typedef struct fc_altitude_control_params {
    fc_altitude_law law;
    fc_ssc_modulation modulation;
    bool adaptive;               /* Theta by (4.83); otherwise Theta = Theta0 */
    bool velocity_measured;      /* relative degree one; false: lead filter (4.18) */

    fc_real dt_s;                /* DT */
    fc_real gravity_mps2;        /* ACCEL */
    fc_real theta0_kg;           /* MASS: nominal Theta = m / (k_h k_g), and Theta(0) */
    fc_real mass_min_kg;         /* MASS: bounds of m, for kp_min, kp_max (4.15) */
    fc_real mass_max_kg;         /* MASS */
    fc_real ground_gain_max;     /* RATIO: k_g_max, the ground-effect bound (k_g_min = 1) */
    fc_real tilt_cos_min;        /* RATIO: k_h_min, tilt compensation stops here, (0, 1] */
    fc_real thrust_min_n;        /* FORCE: body thrust limits */
    fc_real thrust_max_n;        /* FORCE */
    fc_real thrust_authority_n;  /* FORCE: the thrust a normalised 1 stands for (the airframe's
                                  * maximum: fc_allocation_authority_of), [1/16, 2000] N */

    /* SSC */
    fc_real l0_per_s;            /* GAIN: l0 (K1), sigma = e' + l0 e */
    fc_real tau_av_s;            /* DT: averaging filter (4.7) */
    fc_real a_m_per_s;           /* GAIN: prediction-error pole (4.5) */
    fc_real kappa_m_per_kg;      /* GAIN: prediction-error gain (4.5) */
    fc_real rho_n;               /* FORCE: constant modulation, and k of the sign/boundary baselines */
    fc_real delta_n;             /* FORCE: margin delta of (4.39) */
    fc_real k0_ns_per_m;         /* GAIN: k0 of rho = rho_bar + k0 |sigma_tilde| */
    fc_real tau_f_s;             /* DT: lead filter (4.18), relative degree two */
    fc_real gamma;               /* GAIN: adaptation gain (4.83), kg s^2/m^2 */
    fc_real actuator_lag_s;      /* DT: the motors' lag plus the measurement's delay, [0, 1] s;
                                  * 0 for the instant thrust of (3.4) (header, "Lag schedule") */

    /* baselines */
    fc_real boundary_layer_mps;  /* VEL: phi_bl */
    fc_real stw_k1;              /* GAIN: super-twisting, N/(m/s)^(1/2) */
    fc_real stw_k2_nps;          /* GAIN: super-twisting, N/s */
    fc_real pid_kp_z_per_s;      /* GAIN: position loop */
    fc_real pid_ki_z_per_s2;     /* GAIN */
    fc_real pid_kp_v_n_per_mps;  /* GAIN: velocity loop */
    fc_real pid_ki_v_n_per_m;    /* GAIN */
    fc_real pid_vel_limit_mps;   /* VEL: velocity setpoint limit */
} fc_altitude_control_params;

/* The step's input. The reference is by pointer: the caller holds it (the
 * controller, fc_altitude_reference_step's output), the step reads it in
 * place instead of copying it. The pointer must be valid (non-NULL) for the
 * call only: the step reads it during the call and keeps no pointer. Out of
 * range (FC_STEP_BAD_INPUT, the last thrust held): a length beyond
 * +-FC_INPUT_MAX_LENGTH_M, a speed beyond +-FC_INPUT_MAX_SPEED_MPS, an
 * acceleration beyond +-FC_INPUT_MAX_ACCEL_MPS2 (fc/status.h), tilt_cos
 * beyond +-1, or any of them not finite. */
typedef struct fc_altitude_control_input {
    fc_real z_m;                             /* LENGTH: measured altitude, up */
    fc_real vz_mps;                          /* VEL: measured vertical speed, up (ignored without
                                              * velocity_measured, but checked) */
    const fc_vertical_trajectory *reference; /* z_r, z_r', z_r'' (LENGTH, VEL, ACCEL) */
    fc_real tilt_cos;                        /* RATIO: k_h = cos(roll) cos(pitch), measured, [-1, 1]
                                              * (compensated down to tilt_cos_min only) */
    uint8_t allocation_saturation;           /* FC_SAT_THRUST_HIGH/LOW from the allocation (anti-windup) */
} fc_altitude_control_input;

typedef struct fc_altitude_control_output {
    fc_real16 thrust;            /* NORM16: body thrust command / thrust_authority_n, for the
                                  * allocation (SPEC "Units between modules") */
    fc_real thrust_n;            /* FORCE: the same in N, inside the limits */
    fc_real vertical_force_n;    /* FORCE: u, before tilt compensation and clamp */
    /* telemetry */
    fc_real error_m;             /* LENGTH: e */
    fc_real sigma_mps;           /* VEL: sigma (or sigma_hat) */
    fc_real sigma_tilde_mps;     /* VEL */
    fc_real rho_n;               /* FORCE: modulation in use */
    fc_real u0_av_n;             /* FORCE */
    fc_real u_nom_n;             /* FORCE */
    fc_real theta_kg;            /* MASS: Theta_I, the adapted parameter (Theta0 when not adaptive) */
    fc_real observer_bound_n;    /* FORCE: the norm observer's bound of the equivalent
                                  * disturbance, rho - delta - k0 |sigma_tilde| (0 if none) */
    bool clamped;                /* the thrust command was clamped */
} fc_altitude_control_output;

/* The constants the step multiplies a signal by, as gains (fc/scalar.h,
 * fc_gain: a 16-bit mantissa and its own exponent in fixed, the float in
 * float), set at init. A filter pole b near 1 is held as its distance 1 - b
 * (the filter written x <- x - (1 - b) x + ..., fc/scalar.h). Those of the
 * SSC's every step first: on the ATmega a field within 63 bytes of the
 * structure's start is one load, further ones an address computed first. */
typedef struct fc_altitude_gains {
    fc_gain l0;                  /* l0, 1/s */
    fc_gain thrust_max;          /* N */
    fc_gain thrust_min;          /* N */
    fc_gain avg;                 /* 1 - a: the averaging filter (4.7) */
    fc_gain pred_decay;          /* 1 - b: the prediction-error loop (4.5) */
    fc_gain pred_input;          /* kappa_m c, s/kg */
    fc_gain gamma_dt;            /* gamma dt, kg s^3/m^2 */
    fc_gain damping_lp;          /* 1 - e^(-dt/tau_p) */
    fc_gain gamma_p;             /* kg s^3/m^2 */
    fc_gain inv_thrust_authority; /* 1/N */
    fc_gain k0;                  /* k0, N s/m */
    fc_gain rho;                 /* the constant rho, N (and k of the sign/boundary baselines) */
    fc_gain lead;                /* 1 - f: the lead filter (4.18) */
    fc_gain lead_inv_tau;        /* 1/tau_f, 1/s */
    fc_gain lead_state;          /* 1 - tau_f l0 */
    fc_gain obs_decay;           /* 1 - p: the norm observer (4.40) */
    fc_gain obs_input;           /* (1 - p) kappa_m / kp_min */
    fc_gain kp_max;              /* 1/kg */
    fc_gain kp_min;              /* 1/kg */
    fc_gain inv_kappa;           /* 1/kappa_m, kg */
    fc_gain a_m_over_kappa;      /* a_m/kappa_m, kg/s */
    fc_gain eta1;                /* c_eta */
    fc_gain l0_sq;               /* l0^2, 1/s^2 */
    fc_gain eta_kp[FC_ALT_ETA_CELLS + 1];     /* kp_j of the eta norm observer's grid, 1/kg */
    fc_gain eta_fast_decay[FC_ALT_ETA_CELLS]; /* 1 - e^(-l_f dt) */
    fc_gain eta_fast_input[FC_ALT_ETA_CELLS]; /* (1 - e^(-l_f dt))/l_f, s */
    fc_gain eta_fast[FC_ALT_ETA_CELLS];       /* c_f, kg/s */
    fc_gain eta_slow_decay[FC_ALT_ETA_CELLS]; /* 1 - e^(-l_s dt) */
    fc_gain eta_slow_input[FC_ALT_ETA_CELLS]; /* (1 - e^(-l_s dt))/l_s, s */
    fc_gain eta_slow[FC_ALT_ETA_CELLS];       /* c_s, kg/s */
    fc_gain theta0;              /* Theta0, kg: the PID's feed-forward */
    fc_gain dt;                  /* dt, s: the baselines' integrators */
    fc_gain inv_boundary_layer;  /* 1/phi_bl, s/m */
    fc_gain stw_k1;              /* N/(m/s)^(1/2) */
    fc_gain pid_kp_z;            /* 1/s */
    fc_gain pid_ki_z;            /* 1/s^2 */
    fc_gain pid_kp_v;            /* N s/m */
    fc_gain pid_ki_v;            /* N/m */
} fc_altitude_gains;

/* The saturation record first (its address is the structure's), then what
 * every step reads and writes, then the rest (see fc_altitude_gains). */
typedef struct fc_altitude_control {
    fc_arith ar;
    bool ready;
    bool hold;                   /* fc_altitude_control_hold */
    bool lead_primed;
    bool eta_primed;             /* eta_last_kp_d_mps2 holds a step's values */
    /* states */
    fc_real u0_av_n;             /* FORCE */
    fc_real sigma_bar_mps;       /* VEL */
    fc_real theta_kg;            /* MASS: Theta_I, the integral part of the adaptation */
    fc_real sigma_phi_lp;        /* SIGMA_PHI: sigma phi low-passed for the proportional part */
    fc_real u0_n;                /* FORCE: the relay output held over the step */
    fc_real last_error_m;        /* LENGTH */
    fc_real last_thrust_n;       /* FORCE */
    fc_altitude_gains k;         /* the step's constants as gains */
    fc_real omega5_n;            /* FORCE: norm observer (4.40) */
    fc_real last_omega4_n;       /* FORCE: w4 of the last step */
    fc_real omega_eta_fast_mps[FC_ALT_ETA_CELLS]; /* VEL: eta norm observer states (of |kp D|) */
    fc_real omega_eta_slow_mps[FC_ALT_ETA_CELLS]; /* VEL */
    fc_real eta_last_kp_d_mps2[FC_ALT_ETA_CELLS + 1]; /* ACCEL: kp_j D of the last step */
    fc_real lead_state_m;        /* LENGTH: x_f of (4.18) */
    fc_real stw_v_n;             /* FORCE: super-twisting integral */
    fc_real pid_int_z_m;         /* LENGTH x s: position integral, as LENGTH */
    fc_real pid_int_v_m;         /* LENGTH: velocity integral (of a velocity error) */
    /* constants of the discretisation, computed at init */
    fc_real theta_min_kg;        /* MASS: 1 / kp_max */
    fc_real theta_max_kg;        /* MASS: 1 / kp_min = m_max / (k_g_min k_h_min) */
    fc_real ref_accel_max_mps2;  /* ACCEL: z_r'' fed forward up to max(thrust_max/Theta_max - g, 0) */
    fc_real ref_accel_min_mps2;  /* ACCEL: and down to min(thrust_min/Theta_min - g, 0) */
    fc_real sigma_phi_max;       /* SIGMA_PHI: (Theta_max - Theta_min) / gamma_p */
    fc_real lag_divisor;         /* RATIO: 1 + w_theta L, gamma and zeta divided by it */
    fc_real avg_pole;            /* UNIT: a = e^(-dt/tau_av) */
    fc_real pred_pole;           /* UNIT: b = e^(-a_m dt) */
    fc_real pred_gain;           /* RATIO: kappa_m c, 1/kg x s */
    fc_real obs_pole;            /* UNIT: p */
    fc_real obs_gain;            /* RATIO: (1 - p) kappa_m / kp_min */
    /* eta norm observer (relative degree two), computed at init (header comment) */
    fc_real eta_kp_per_kg[FC_ALT_ETA_CELLS + 1]; /* RATIO: the grid's kp, kp_min .. kp_max */
    fc_real eta_fast_gain_kg_per_s[FC_ALT_ETA_CELLS]; /* GAIN: c_f of each cell */
    fc_real eta_fast_pole[FC_ALT_ETA_CELLS];    /* UNIT: e^(-l_f dt) */
    fc_real eta_slow_gain_kg_per_s[FC_ALT_ETA_CELLS]; /* GAIN: c_s */
    fc_real eta_slow_pole[FC_ALT_ETA_CELLS];    /* UNIT: e^(-l_s dt) */
    fc_real kp_max_over_kappa;   /* RATIO: kp_max / kappa_m */
    fc_real inv_kappa_kg;        /* MASS: 1 / kappa_m */
    fc_real a_m_over_kappa;      /* MASS: a_m / kappa_m, kg/s */
    fc_real kp_max_per_kg;       /* RATIO: k_g_max / m_min (k_h <= 1) */
    fc_real kp_min_per_kg;       /* RATIO: 1 / Theta_max */
    fc_altitude_control_params p;
} fc_altitude_control;

/* The variants the SIL and the platforms select by name or number. */
typedef enum fc_altitude_variant {
    FC_ALT_VARIANT_SSC = 0,            /* "ssc": rel. degree one, constant rho, Theta0 (4.4) */
    FC_ALT_VARIANT_SSC_ADAPTIVE,       /* "ssc-adaptive": the same with the Theta law (4.4) */
    FC_ALT_VARIANT_SSC_NORM,           /* "ssc-norm": rho from the norm observer (4.40)-(4.43) */
    FC_ALT_VARIANT_SSC_NORM_ADAPTIVE,  /* "ssc-norm-adaptive" */
    FC_ALT_VARIANT_SSC_EXTRA,          /* "ssc-extra": rho from u0_av (4.54)-(4.56) */
    FC_ALT_VARIANT_SSC_REL2,           /* "ssc-rel2": z' not measured, lead filter (4.18), constant rho */
    FC_ALT_VARIANT_SSC_REL2_ADAPTIVE,  /* "ssc-rel2-adaptive" */
    FC_ALT_VARIANT_SSC_REL2_NORM,      /* "ssc-rel2-norm": eta norm observer (4.3.2) */
    FC_ALT_VARIANT_PID,                /* "pid": the Crazyflie's cascade */
    FC_ALT_VARIANT_SMC,                /* "smc": first-order sliding mode, sign */
    FC_ALT_VARIANT_SMC_BOUNDARY,       /* "smc-boundary": boundary layer */
    FC_ALT_VARIANT_SUPER_TWISTING,     /* "super-twisting" */
    FC_ALT_VARIANT_COUNT
} fc_altitude_variant;

/* Default parameters (below) switched to variant v. Relative degree two uses
 * kappa_m = 0.5: with kappa_m = 1 the eta-dynamics are not minimum phase for
 * masses up to 5 kg (Remark 9, tau_av kappa_m l0 = 0.2 = kp_min). */
void fc_altitude_control_variant_params(fc_altitude_control_params *p, fc_altitude_variant v, fc_real dt_s,
                                        fc_real mass_kg);

/* The parameters of the dissertation's 4.4 simulation for a vehicle of nominal
 * mass mass_kg (rho = 50, tau_av = 0.1, l0 = 2, a_m = 5, kappa_m = 1, gamma = 5,
 * thrust in [0, 2 m g]), with the law, modulation and adaptation given. */
void fc_altitude_control_default_params(fc_altitude_control_params *p, fc_real dt_s, fc_real mass_kg);

/* Theta0 = mass_kg and the mass bounds for payload changes of -25 % / +25 %
 * (the gains stay as they are). */
void fc_altitude_control_set_mass(fc_altitude_control_params *p, fc_real mass_kg);

fc_init_result fc_altitude_control_init(fc_altitude_control *c, const fc_altitude_control_params *p);

/* Clear the states (filters, integrators, Theta back to Theta0). */
void fc_altitude_control_reset(fc_altitude_control *c);

/* While held, Theta does not adapt (Theta_I frozen, the proportional part
 * fading out) and the baselines' integrators do not integrate, as while the
 * thrust is clamped; the law itself runs on. For inputs that are estimates
 * standing in for lost measurements (fc/failsafe.h's hold): what is learnt
 * must come from measurements; and for a landing once contact is planned. */
void fc_altitude_control_hold(fc_altitude_control *c, bool hold);

fc_step_status fc_altitude_control_step(fc_altitude_control *c, const fc_altitude_control_input *in,
                                        fc_altitude_control_output *out);

#endif /* FC_ALTITUDE_CONTROL_H */
