// Builds estimators by name. Each estimator family registers its names in
// the table below; families outside gvs::dsp add theirs with add_estimators().
#include <algorithm>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/gvs_estimator.hpp"
#include "gvs/dsp/thesis.hpp"

namespace gvs::dsp {

namespace {

// ENTRIES (one line each; keep alphabetical within a family)
constexpr EstimatorMaker kEstimators[] = {
    {"none", nullptr},
    {"gvs", &make_gvs_estimator},
    {"thesis-fft", &make_thesis_fft_estimator},
    {"thesis-laplacian", &make_thesis_laplacian_estimator},
};

// Methods of the desk tool only (gvs::dsp_orb, gvs/dsp/thesis_orb_methods.hpp):
// named here so that a program without them says where they are.
constexpr std::string_view kDeskOnly[] = {"thesis", "thesis-orb"};

/// What add_estimators() added, in the order added.
struct Added {
  std::mutex mutex;
  std::vector<EstimatorMaker> makers;
};

Added& added() {
  static Added a;
  return a;
}

std::vector<EstimatorMaker> all_makers() {
  std::vector<EstimatorMaker> all;
  for (const EstimatorMaker& e : kEstimators) {
    if (e.make != nullptr) all.push_back(e);
  }
  Added& a = added();
  const std::lock_guard lock(a.mutex);
  all.insert(all.end(), a.makers.begin(), a.makers.end());
  return all;
}

}  // namespace

void add_estimators(std::span<const EstimatorMaker> makers) {
  Added& a = added();
  const std::lock_guard lock(a.mutex);
  for (const EstimatorMaker& m : makers) {
    const auto same = [&](const EstimatorMaker& e) { return std::string_view(e.name) == m.name; };
    if (m.make != nullptr && std::none_of(a.makers.begin(), a.makers.end(), same)) a.makers.push_back(m);
  }
}

std::vector<std::string> estimator_names() {
  std::vector<std::string> names;
  for (const EstimatorMaker& e : all_makers()) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<VelocityEstimator> make_estimator(const EstimatorConfig& config) {
  for (const EstimatorMaker& e : all_makers()) {
    if (config.method == e.name) return e.make(config);
  }
  std::ostringstream msg;
  msg << "unknown estimator method '" << config.method << "'; choose one of:";
  for (const std::string& n : estimator_names()) msg << ' ' << n;
  if (std::find(std::begin(kDeskOnly), std::end(kDeskOnly), config.method) != std::end(kDeskOnly)) {
    msg << " ('" << config.method
        << "' uses ORB, OpenCV's features2d, which this program is built without: the desk tool `gvs` has it, "
           "e.g. gvs replay --method "
        << config.method << ")";
  }
  throw std::invalid_argument(msg.str());
}

}  // namespace gvs::dsp
