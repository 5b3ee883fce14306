// Umbrella header of the estimator (lashid::estimator): the DIS/AIS identification schemes of
//   F. Giri, Y. Rochdi, A. Brouri, F.Z. Chaoui, "Identification of block-oriented systems in the presence of
//   nonparametric input nonlinearities of switch and backlash types", Automatica,
// header-only, heap-free, no I/O. SchemeIdentifier<Scalar, N, M> takes the samples of one scheme's step and pulse
// experiments (ExcitationGenerator makes their inputs) and returns a, b and the border points; cross_check compares
// the two schemes (Remark 3b). docs/estimator.md, docs/package.md.
#pragma once

#include "lashid/estimator/cross_check.hpp"
#include "lashid/estimator/design.hpp"
#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/estimator/paper_designs.hpp"
#include "lashid/estimator/status.hpp"
