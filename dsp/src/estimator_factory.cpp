// Builds estimators by name. Each estimator family registers its names in
// the table below.
#include <sstream>
#include <stdexcept>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/gvs_estimator.hpp"
#include "gvs/dsp/thesis.hpp"

namespace gvs::dsp {

namespace {

using Maker = std::unique_ptr<VelocityEstimator> (*)(const EstimatorConfig&);

struct Entry {
  const char* name;
  Maker make;
};

// ENTRIES (one line each; keep alphabetical within a family)
constexpr Entry kEstimators[] = {
    {"none", nullptr},
    {"gvs", &make_gvs_estimator},
    {"thesis", &make_thesis_estimator},
    {"thesis-fft", &make_thesis_fft_estimator},
    {"thesis-laplacian", &make_thesis_laplacian_estimator},
    {"thesis-orb", &make_thesis_orb_estimator},
};

}  // namespace

std::vector<std::string> estimator_names() {
  std::vector<std::string> names;
  for (const Entry& e : kEstimators) {
    if (e.make != nullptr) names.emplace_back(e.name);
  }
  return names;
}

std::unique_ptr<VelocityEstimator> make_estimator(const EstimatorConfig& config) {
  for (const Entry& e : kEstimators) {
    if (e.make != nullptr && config.method == e.name) return e.make(config);
  }
  std::ostringstream msg;
  msg << "unknown estimator method '" << config.method << "'; choose one of:";
  for (const std::string& n : estimator_names()) msg << ' ' << n;
  throw std::invalid_argument(msg.str());
}

}  // namespace gvs::dsp
