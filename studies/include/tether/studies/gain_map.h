// What a gain_map figure marks on the (alpha, beta) plane of each panel (a combination of the swept columns
// other than /stabilization/alpha and /stabilization/beta; the panel's integrator and step come from its scene).
//
// The stability bound: with alpha = 2 zeta omega and beta = omega^2, the constraint error's discrete dynamics
// stay stable while h omega <= B(zeta) (stability.h). For zeta on a log grid from 1e-4 to 1e4 the curve
//   (alpha, beta) = (2 zeta B(zeta) / h, (B(zeta) / h)^2)
// separates the gains the integrator can follow from those where the error grows by itself.
// The marks: the presets (gain_tuning.h, "none" left out: it is not on a log plane) and the tuned gains of the
// panel's scene (TuneGains with its defaults), with their name.
#pragma once

#include <nlohmann/json.hpp>

#include "tether/studies/study_spec.h"

namespace tether {

// {"panels": [{"values": {COLUMN: cell as in results.csv, ...}, "step": h,
//              "bound": [[alpha, beta], ...], "marks": [{"name", "alpha", "beta"}, ...]}, ...]}
nlohmann::json GainMapMarks(const StudySpec& spec);

}  // namespace tether
