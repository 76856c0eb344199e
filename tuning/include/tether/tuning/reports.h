// The results of gain tuning and of identification as the JSON `tether tune` and `tether identify` / `tether fit`
// print, which the Python module returns too (one builder, so that the two never differ). Numbers that are not
// finite (an objective without a reference, an unavailable standard deviation) are null.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "tether/tuning/gain_tuning.h"
#include "tether/tuning/identification.h"

namespace tether {

// `objective_kind` ("reference" or "drift") and `optimizer` as the user named them; `step` the scene's, s.
nlohmann::json TuneJson(const TuneResult& result, const std::string& objective_kind, const std::string& optimizer,
                        double step);

nlohmann::json IdentifyJson(const ParameterSet& parameters, const IdentifyResult& result, const std::string& optimizer);

}  // namespace tether
