// The health line is made from the declared counters (GVS_HEALTH_COUNTERS):
// every shown counter appears with its text, deltas where declared, the
// light part and the errno only when they have something to say.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "gvs/daemon/health.hpp"

namespace gvs::daemon {
namespace {

TEST(HealthFields, LineShowsEveryDeclaredCounterAsDeclared) {
  HealthSnapshot prev;
  HealthSnapshot now;
  int k = 0;
  // Distinct values, each 3 above the previous line's.
#define GVS_SET(name, type, ...)                        \
  ++k;                                                  \
  now.name = static_cast<type>(1000 + 10 * k);          \
  prev.name = static_cast<type>(1000 + 10 * k - 3);
  GVS_HEALTH_COUNTERS(GVS_SET)
#undef GVS_SET
  const std::string line = format_health_line(now, prev, PublishedEstimate{}, 0, 5.0);
  int shown = 0;
  for (const HealthField& f : kHealthFields) {
    const std::int64_t v = f.value(now);
    std::string item = fmt::format(fmt::runtime(f.text), fmt::arg("v", v), fmt::arg("rate", 3 / 5.0),
                                   fmt::arg("ms", static_cast<double>(v) / 1e6));
    if (f.show == HealthShow::delta || f.show == HealthShow::delta_by_reason) item += " (+3)";
    if (f.show == HealthShow::hidden) {
      EXPECT_EQ(line.find(std::to_string(v)), std::string::npos) << f.name << " is hidden: " << line;
      continue;
    }
    ++shown;
    EXPECT_NE(line.find(item), std::string::npos) << f.name << ": '" << item << "' in " << line;
    EXPECT_NE(f.help[0], '\0') << f.name;
    EXPECT_NE(f.unit[0], '\0') << f.name;
  }
  EXPECT_GT(shown, 0);
  EXPECT_NE(line.find(" | light "), std::string::npos) << line;
  EXPECT_NE(line.find(" | height "), std::string::npos) << line;

  const std::string quiet = format_health_line(HealthSnapshot{}, HealthSnapshot{}, PublishedEstimate{}, 0, 5.0);
  EXPECT_EQ(quiet.find("light"), std::string::npos) << "no [light] driver ran: " << quiet;
  EXPECT_EQ(quiet.find("height"), std::string::npos) << "no [height] source = \"can\": " << quiet;
  EXPECT_EQ(quiet.find("last errno"), std::string::npos) << quiet;
  EXPECT_NE(quiet.find("ring overruns 0 (+0)"), std::string::npos) << quiet;
}

}  // namespace
}  // namespace gvs::daemon
