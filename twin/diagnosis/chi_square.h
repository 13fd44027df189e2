#pragma once
// Tail probabilities for the significance tests of the residual analysis.

namespace twin::diagnosis {

// Regularized upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0: by its
// power series for P = 1 - Q when x < a + 1, else by Lentz's continued fraction (Numerical
// Recipes' split; both converge fast there). Relative accuracy ~1e-12.
double upper_incomplete_gamma_q(double a, double x);

// Upper tail P(X >= x) of chi-square with `dof` (> 0) degrees of freedom: Q(dof / 2, x / 2).
double chi_square_upper_tail(double x, double dof);

// Two-sided p-value of a Pearson correlation r over n independent pairs (Fisher's z,
// z = atanh(r) sqrt(n - 3) ~ N(0, 1)); 1 when n < 4.
double correlation_p_value(double r, int n);

}  // namespace twin::diagnosis
