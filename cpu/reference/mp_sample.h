/* mp_sample.h: sampling d'Eon's longitudinal lobe M_p (Eq. 7; deon_ref.h slref_deon_log_mp),
 * exactly. M_p(v, theta_i, theta_o') cos theta_i is the distribution of the inclination of a
 * direction drawn from the von Mises-Fisher distribution of concentration 1/v around a mean
 * direction of inclination -theta_o' (d'Eon's derivation: integrating the vMF over the azimuth
 * about the fiber axis gives the I0 of Eq. 7). So: draw the angle to the mean from the vMF
 * (cos = 1 + v log(u1 + (1 - u1) e^(-2/v))), a uniform azimuth about the mean, and take the
 * component along u. This is pbrt-v4's HairBxDF::Sample_f closed form, here without its clamp
 * of u1 (which would make the samples' density differ from M_p near cos = -1). */
#ifndef SL_MP_SAMPLE_H
#define SL_MP_SAMPLE_H

/* theta_i in [-pi/2, pi/2] with density M_p(v, theta_i, theta_op) cos theta_i, from two uniforms
 * in [0, 1). v > 0; theta_op may lie beyond +-pi/2 (a tilted lobe). */
double slref_mp_sample(double v, double theta_op, double u1, double u2);

#endif
