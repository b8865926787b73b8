#pragma once
// Symmetric compositions of a symmetric order-2 one-step map Φ_h (the LGVI's Hamiltonian
// forms): Φ_{γ_s h} ∘ … ∘ Φ_{γ_1 h}, with Σ γ_i = 1 and γ_i = γ_{s+1−i}, of order 4 or 6
// (docs/equations.md §4; Hairer, Lubich & Wanner 2006, §V.3).
#include <string>
#include <vector>

namespace lgvi {

// γ_1 … γ_s of the named composition of `order`, or empty when there is none:
//   order 4  yoshida    3 stages  γ1 = 1/(2 − 2^{1/3}), γ2 = 1 − 2γ1          (Yoshida 1990)
//            suzuki     5 stages  p, p, 1 − 4p, p, p with p = 1/(4 − 4^{1/3})  (Suzuki 1990)
//            mclachlan  5 stages  0.28, 0.6254664…, γ3 = 1 − 2(γ1 + γ2)         (McLachlan 1995)
//   order 6  yoshida    7 stages  Yoshida 1990, solution A
//            kahan-li   9 stages  Kahan & Li 1997 (HLW 2006 §V.3.2); its error constant is
//                                 25× smaller than yoshida's at order 6 (measured,
//                                 docs/numerical-results.md "Compositions")
std::vector<double> composition_coefficients(int order, const std::string& name);

// "known: …" for an error message.
std::string compositions_of_order(int order);

}  // namespace lgvi
