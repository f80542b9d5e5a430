// The outcome of estimating one frame: which measurement gave the estimate,
// or why there is none. One table gives each outcome its word in the
// estimates CSV (shared/spec/dataset-format.md), its code in the CAN signal
// GVS_Method (can/gvs.dbc, docs/can-interface.md) and a description.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <optional>
#include <string_view>

namespace gvs::core {

/// Every outcome an estimator, the daemon's frame checks or a test source
/// can report. The order is the order of kMethods.
enum class Method : std::uint8_t {
  none,
  // no estimate: the frame
  dark,
  saturated,
  no_texture,
  bad_frame,
  no_match,
  short_streak,
  empty_frame,
  bad_format,
  wrong_size,
  no_previous,
  bad_time,
  no_model,
  error,
  // no estimate: the daemon's frame checks and the camera
  bad_exposure,
  time_backwards,
  unreadable,
  no_light_in_exposure,
  no_exposure_metadata,
  estimator_exception,
  // the thesis's estimators
  thesis_orb,
  thesis_fft,
  thesis_laplacian,
  thesis_lap,
  thesis_lap_orb,
  thesis_lap_fft,
  // the gvs estimator
  still,
  pair,
  blur_cont,
  blur_energy,
  blur_fwd,
  streak_cont,
  streak_energy,
  streak_fwd,
  dpiv_cont,
  dpiv_energy,
  dpiv_fwd,
  // the source's ground truth (gvsd's "truth" estimator)
  truth,
  // a word read from an estimates CSV that is not in this table
  unknown,
};

struct MethodInfo {
  Method method;
  const char* word;          ///< the estimates CSV's `method` column
  std::uint8_t can_code;     ///< the value of GVS_Method
  const char* description;
};

// clang-format off
inline constexpr MethodInfo kMethods[] = {
    {Method::none,                 "none",                 0,  "no estimate yet, or no truth for this frame"},
    {Method::dark,                 "dark",                 1,  "too little light to see the ground"},
    {Method::saturated,            "saturated",            2,  "too much of the frame is at full scale"},
    {Method::no_texture,           "no-texture",           3,  "not enough ground texture above the sensor's noise"},
    {Method::bad_frame,            "bad-frame",            4,  "the gvs estimator got a frame of the wrong size or pixel format"},
    {Method::no_match,             "no-match",             5,  "no displacement or streak was found"},
    {Method::short_streak,         "short-streak",         6,  "blur too short to show its axis: no direction"},
    {Method::empty_frame,          "empty-frame",          7,  "a thesis estimator got a frame without pixels"},
    {Method::bad_format,           "bad-format",           8,  "a thesis estimator got a frame that is not 8-bit grey"},
    {Method::wrong_size,           "wrong-size",           9,  "the frame's size differs from the camera geometry"},
    {Method::no_previous,          "no-previous",          10, "first frame of a two-frame method"},
    {Method::bad_time,             "bad-time",             11, "the frame is not later than the one before"},
    {Method::no_model,             "no-model",             12, "the Laplacian speed model is not loaded"},
    {Method::error,                "error",                13, "the thesis estimator failed on this frame"},
    {Method::bad_exposure,         "bad-exposure",         48, "exposure time missing, not positive or too long"},
    {Method::time_backwards,       "time-backwards",       49, "the frame's time is not after the previous frame's"},
    {Method::unreadable,           "unreadable",           50, "the source could not deliver the frame's pixels"},
    {Method::no_light_in_exposure, "no-light-in-exposure", 51, "the LED ring fired no light in this frame's exposure"},
    {Method::no_exposure_metadata, "no-exposure-metadata", 52, "the camera did not say how long the frame was exposed"},
    {Method::estimator_exception,  "estimator-exception",  53, "the estimator threw on this frame; gvsd caught it and reset the estimator"},
    {Method::thesis_orb,           "thesis-orb",           16, "thesis: ORB feature matching between two frames"},
    {Method::thesis_fft,           "thesis-fft",           17, "thesis: streak axis from the spectrum (direction only)"},
    {Method::thesis_laplacian,     "thesis-laplacian",     18, "thesis: speed from the Laplacian blur measure"},
    {Method::thesis_lap,           "thesis-lap",           19, "thesis: Laplacian speed, no direction found"},
    {Method::thesis_lap_orb,       "thesis-lap-orb",       20, "thesis: Laplacian speed, ORB direction"},
    {Method::thesis_lap_fft,       "thesis-lap-fft",       21, "thesis: Laplacian speed, spectrum direction"},
    {Method::still,                "still",                32, "the ground did not move between two frames: standstill"},
    {Method::pair,                 "pair",                 33, "displacement between two consecutive frames"},
    {Method::blur_cont,            "blur-cont",            34, "streak axis and length; sign from continuity"},
    {Method::blur_energy,          "blur-energy",          35, "streak axis and length; sign from the light's energy profile"},
    {Method::blur_fwd,             "blur-fwd",             36, "streak axis and length; sign assumed forwards"},
    {Method::streak_cont,          "streak-cont",          37, "streak longer than measurable: direction only; sign from continuity"},
    {Method::streak_energy,        "streak-energy",        38, "streak longer than measurable: direction only; sign from the energy profile"},
    {Method::streak_fwd,           "streak-fwd",           39, "streak longer than measurable: direction only; sign assumed forwards"},
    {Method::dpiv_cont,            "dpiv-cont",            40, "double-pulse displacement in one frame; sign from continuity"},
    {Method::dpiv_energy,          "dpiv-energy",          41, "double-pulse displacement in one frame; sign from unequal pulses"},
    {Method::dpiv_fwd,             "dpiv-fwd",             42, "double-pulse displacement in one frame; sign assumed forwards"},
    {Method::truth,                "truth",                64, "the source's ground truth (pipeline tests)"},
    {Method::unknown,              "unknown",              255, "an estimates CSV word this program does not know"},
};
// clang-format on

inline constexpr std::size_t kMethodCount = std::size(kMethods);

namespace detail {
constexpr bool methods_in_enum_order() {
  for (std::size_t i = 0; i < kMethodCount; ++i) {
    if (static_cast<std::size_t>(kMethods[i].method) != i) return false;
  }
  return true;
}
constexpr bool words_and_codes_unique() {
  for (std::size_t i = 0; i < kMethodCount; ++i) {
    for (std::size_t j = i + 1; j < kMethodCount; ++j) {
      if (kMethods[i].can_code == kMethods[j].can_code) return false;
      if (std::string_view(kMethods[i].word) == std::string_view(kMethods[j].word)) return false;
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::methods_in_enum_order(), "kMethods must list every Method once, in enum order");
static_assert(detail::words_and_codes_unique(), "each method needs its own CSV word and CAN code");

constexpr const MethodInfo& method_info(Method m) { return kMethods[static_cast<std::size_t>(m)]; }
/// The estimates CSV word ("pair", "no-texture", ...).
constexpr const char* method_word(Method m) { return method_info(m).word; }
/// The GVS_Method code.
constexpr std::uint8_t method_can_code(Method m) { return method_info(m).can_code; }

/// The method of a CSV word; nullopt for a word not in the table.
constexpr std::optional<Method> method_from_word(std::string_view word) {
  for (const MethodInfo& m : kMethods) {
    if (word == m.word) return m.method;
  }
  return std::nullopt;
}
/// The method of a GVS_Method code; nullopt for a code not in the table.
constexpr std::optional<Method> method_from_can_code(std::uint8_t code) {
  for (const MethodInfo& m : kMethods) {
    if (m.can_code == code) return m.method;
  }
  return std::nullopt;
}

/// Writes the CSV word (for test messages and logs).
/// The method's word, for logs and test messages.
inline std::ostream& operator<<(std::ostream& out, Method m) { return out << method_word(m); }

}  // namespace gvs::core
