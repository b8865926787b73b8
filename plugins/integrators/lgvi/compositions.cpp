// The composition coefficients of compositions.hpp. The tables list γ_1 … γ_m up to the middle
// stage; the rest follows by symmetry, and the middle one is 1 − 2 Σ of the others (so Σ γ = 1
// to round-off whatever the digits printed).
#include "compositions.hpp"

#include <cmath>

namespace lgvi {

namespace {

std::vector<double> symmetric(std::vector<double> half) {  // γ_1 … γ_{m−1} → γ_1 … γ_{2m−1}
  double sum = 0.0;
  for (double g : half) sum += g;
  std::vector<double> gamma = half;
  gamma.push_back(1.0 - 2.0 * sum);
  gamma.insert(gamma.end(), half.rbegin(), half.rend());
  return gamma;
}

}  // namespace

std::vector<double> composition_coefficients(int order, const std::string& name) {
  if (order == 4 && name == "yoshida") return symmetric({1.0 / (2.0 - std::cbrt(2.0))});
  if (order == 4 && name == "suzuki") {
    const double p = 1.0 / (4.0 - std::cbrt(4.0));
    return symmetric({p, p});
  }
  if (order == 4 && name == "mclachlan") return symmetric({0.28, 0.62546642846767004501});
  if (order == 6 && name == "yoshida")
    return symmetric({0.78451361047755726381949763, 0.23557321335935813368479318, -1.17767998417887100694641568});
  if (order == 6 && name == "kahan-li")
    return symmetric({0.39216144400731413927925056, 0.33259913678935943859974864, -0.70624617255763935980996482,
                      0.08221359629355080023149045});
  return {};
}

std::string compositions_of_order(int order) {
  if (order == 4) return "known: yoshida, suzuki, mclachlan";
  if (order == 6) return "known: yoshida, kahan-li";
  return "compositions have order 4 or 6";
}

}  // namespace lgvi
