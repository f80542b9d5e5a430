// The table of configuration keys: the example file and the reference in
// docs/daemon.md are its output, every key parses its default and refuses
// what is outside its range naming itself, SIGHUP applies exactly the keys
// the table marks, and --check-config's start-up checks refuse what start-up
// refuses without opening a device.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <variant>
#include <vector>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/config_keys.hpp"
#include "gvs/daemon/source_factory.hpp"
#include "gvs/daemon/startup_check.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/simulator.hpp"

namespace gvs::daemon {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  EXPECT_TRUE(in.good()) << p;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string refusal(const std::string& toml) {
  try {
    (void)parse_config(toml, "t.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string section_text(const ConfigKey& key, const std::string& line) {
  return std::string("[").append(key.section).append("]\n").append(line).append("\n");
}

bool is_real(const ConfigKey& key) {
  DaemonConfig c;
  return std::holds_alternative<double*>(key.field(c));
}

TEST(ConfigTable, ExampleFileIsTheTablesOutput) {
  const std::string file = slurp(std::filesystem::path(GVSD_SOURCE_DIR) / "systemd" / "gvsd.toml");
  EXPECT_EQ(file, example_config_text())
      << "systemd/gvsd.toml differs from the table: gvsd --print-example-config > systemd/gvsd.toml";
}

TEST(ConfigTable, DocsReferenceIsTheTablesOutput) {
  const std::string doc = slurp(std::filesystem::path(GVSD_SOURCE_DIR) / "docs" / "daemon.md");
  const std::string begin = "<!-- begin: gvsd --print-config-reference -->\n";
  const std::string end = "<!-- end: gvsd --print-config-reference -->";
  const auto b = doc.find(begin);
  const auto e = doc.find(end);
  ASSERT_NE(b, std::string::npos) << "docs/daemon.md lacks " << begin;
  ASSERT_NE(e, std::string::npos) << "docs/daemon.md lacks " << end;
  EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), config_reference_markdown())
      << "docs/daemon.md's configuration reference differs from the table: replace it with the output of "
         "gvsd --print-config-reference";
}

TEST(ConfigTable, EachKeyIsDeclaredOnceWithItsOwnField) {
  std::set<std::string> paths;
  std::set<const void*> fields;
  DaemonConfig c;
  std::set<std::string> sections;
  for (const ConfigSection& s : config_sections()) sections.emplace(s.name);
  for (const ConfigKey& key : config_keys()) {
    EXPECT_TRUE(paths.insert(key_path(key)).second) << key_path(key) << " declared twice";
    const void* field = std::visit([](auto* p) -> const void* { return p; }, key.field(c));
    EXPECT_TRUE(fields.insert(field).second) << key_path(key) << " shares its field with another key";
    EXPECT_EQ(sections.count(std::string(key.section)), 1u) << key_path(key) << ": section not declared";
    EXPECT_FALSE(key.help.empty()) << key_path(key);
  }
}

TEST(ConfigTable, EveryKeyParsesItsDefaultAndRefusesWhatIsOutsideItsRange) {
  const DaemonConfig defaults;
  for (const ConfigKey& key : config_keys()) {
    const std::string path = key_path(key);
    const std::string named = std::string("[").append(key.section).append("] ").append(key.name);
    // The value the example shows parses back to the field's value.
    const std::string shown = key.example.empty() ? toml_value(key, defaults) : std::string(key.example);
    const DaemonConfig parsed = parse_config(section_text(key, std::string(key.name) + " = " + shown), "t.toml");
    if (key.example.empty()) {
      EXPECT_TRUE(same_value(key, parsed, defaults)) << path << " = " << shown;
    } else {
      EXPECT_EQ(toml_value(key, parsed), shown) << path;
    }

    DaemonConfig c;
    const ConfigField f = key.field(c);
    if (std::holds_alternative<bool*>(f)) {
      EXPECT_NE(refusal(section_text(key, std::string(key.name) + " = 1")).find(named + " must be true or false"),
                std::string::npos)
          << path;
    } else if (std::holds_alternative<std::string*>(f)) {
      EXPECT_NE(refusal(section_text(key, std::string(key.name) + " = 3")).find(named + " must be a string"),
                std::string::npos)
          << path;
      EXPECT_NE(refusal(section_text(key, std::string(key.name) + " = \"\"")).find(named + " must not be empty"),
                std::string::npos)
          << path;
      if (key.allowed != nullptr) {
        const std::string e = refusal(section_text(key, std::string(key.name) + " = \"no-such-value\""));
        EXPECT_NE(e.find(named + " = \"no-such-value\" is not allowed (one of: "), std::string::npos) << e;
      }
    } else {
      std::vector<std::string> outside;
      if (is_real(key)) {
        const double step = std::max(0.001, (key.max - key.min) * 0.001);
        for (const double v : {key.min - step, key.max + step}) {
          std::ostringstream text;
          text.precision(17);
          text << std::showpoint << v;
          outside.push_back(text.str());
        }
      } else {
        outside = {std::to_string(static_cast<std::int64_t>(key.min) - 1),
                   std::to_string(static_cast<std::int64_t>(key.max) + 1)};
      }
      for (const std::string& v : outside) {
        const std::string line = std::string(key.name) + " = " + v;
        const std::string e = refusal(section_text(key, line));
        EXPECT_NE(e.find("t.toml:2: " + named + " = "), std::string::npos) << line << " -> " << e;
        EXPECT_NE(e.find("is out of range (allowed "), std::string::npos) << line << " -> " << e;
      }
      const std::string e = refusal(section_text(key, std::string(key.name) + " = \"x\""));
      EXPECT_NE(e.find(named + (is_real(key) ? " must be a number" : " must be an integer")), std::string::npos)
          << e;
    }
  }
}

/// A valid value of the key other than `c`'s.
void change(const ConfigKey& key, DaemonConfig& c) {
  std::visit(
      [&](auto* p) {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, bool>) {
          *p = !*p;
        } else if constexpr (std::is_same_v<T, std::string>) {
          if (key.allowed == nullptr) {
            *p += "-changed";
          } else {
            const std::string was = *p;
            for (const std::string& a : key.allowed()) {
              if (a != was) *p = a;
            }
          }
        } else {
          *p = static_cast<T>(*p == static_cast<T>(key.min) ? key.max : key.min);
        }
      },
      key.field(c));
}

TEST(ConfigTable, SighupAppliesExactlyTheKeysMarkedReloadable) {
  for (const ConfigKey& key : config_keys()) {
    DaemonConfig running;
    DaemonConfig fresh;
    change(key, fresh);
    ASSERT_FALSE(same_value(key, running, fresh)) << key_path(key);
    const auto restart = restart_only_changes(running, fresh);
    const auto applied = apply_reloadable_keys(running, fresh);
    if (key.reload == Reload::sighup) {
      EXPECT_TRUE(restart.empty()) << key_path(key);
      ASSERT_EQ(applied.size(), 1u) << key_path(key);
      EXPECT_EQ(applied[0].rfind(key_path(key) + " = ", 0), 0u) << applied[0];
      EXPECT_TRUE(same_value(key, running, fresh)) << key_path(key) << " was not applied";
    } else {
      ASSERT_EQ(restart.size(), 1u) << key_path(key);
      EXPECT_EQ(restart[0], key_path(key));
      EXPECT_TRUE(applied.empty()) << key_path(key);
      EXPECT_FALSE(same_value(key, running, fresh)) << key_path(key) << " must wait for a restart";
    }
  }
}

// ---- --check-config: start-up's checks without devices ----

std::string startup_refusal(const std::string& toml) {
  try {
    (void)check_startup(parse_config(toml, "t.toml"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(StartupCheck, RefusesWhatStartUpRefuses) {
  // CAN slots aligned to the frames need rates that lock.
  EXPECT_NE(startup_refusal("[can]\nalign_to_frames = true\n").find("[can] align_to_frames: the frame rate 60 fps"),
            std::string::npos)
      << startup_refusal("[can]\nalign_to_frames = true\n");
  EXPECT_EQ(startup_refusal("[can]\nalign_to_frames = true\n[source]\nsim_fps = 100.0\n"), "(accepted)");
  EXPECT_NE(startup_refusal("[can]\nalign_to_frames = true\n[libcamera]\nfps = 90.0\n[source]\nuri = \"libcamera\"\n")
                .find("90 fps"),
            std::string::npos);
  EXPECT_NE(startup_refusal("[source]\nuri = \"sim:nonexistent\"\n").find("unknown scenario 'nonexistent'"),
            std::string::npos);
  EXPECT_NE(startup_refusal("[source]\nuri = \"sim:\"\n").find("name a scenario"), std::string::npos);
  EXPECT_NE(startup_refusal("[source]\nuri = \"tape:x\"\n").find("unknown kind"), std::string::npos);
  EXPECT_NE(startup_refusal("[source]\nuri = \"replay:/nonexistent/run\"\n").find("/nonexistent/run"),
            std::string::npos);
  EXPECT_NE(startup_refusal("[source]\nsim_ground = \"photo:/nonexistent/asphalt.png\"\n")
                .find("/nonexistent/asphalt.png"),
            std::string::npos);
  // 1000 frames/s leaves 1 ms per frame: the simulator refuses a 3 ms exposure.
  EXPECT_NE(startup_refusal("[source]\nsim_fps = 1000\n").find("exposure_us"), std::string::npos);
  EXPECT_NE(startup_refusal("[can]\nuri = \"carrier-pigeon:x\"\n").find("carrier-pigeon"), std::string::npos);
  // The estimator's name is refused by the parser already, naming the key.
  EXPECT_NE(refusal("[estimator]\nmethod = \"foo\"\n").find("[estimator] method = \"foo\" is not allowed"),
            std::string::npos);
}

TEST(StartupCheck, ReplayTakesTheGeometryFromTheDatasetsIndex) {
  const auto dir = std::filesystem::temp_directory_path() / ("gvsd_config_ds_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  drivers::SimulatorConfig sc;
  sc.scenario = "const";
  sc.camera.width_px = 640;
  sc.camera.height_px = 480;
  drivers::Simulator sim(sc);
  drivers::CameraInfo cam;
  cam.geometry = sc.camera;
  {
    drivers::DatasetWriter writer(dir, cam, true);
    drivers::SimFrame f;
    for (int i = 0; i < 4 && sim.next(f); ++i) {
      writer.write_frame(f.gray, f.record);
      writer.write_truth(f.truth);
    }
  }
  DaemonConfig c;
  c.source_uri = "replay:" + dir.string();
  const core::CameraGeometry g = check_frame_source(c).geometry;
  EXPECT_EQ(g.width_px, 640) << "the dataset's camera.json, not [camera]";
  EXPECT_EQ(g.height_px, 480);
  std::filesystem::remove_all(dir);
}

TEST(StartupCheck, OpensNoDevice) {
  // Neither this interface nor a camera exists here: start-up would fail
  // opening them, the check does not try.
  EXPECT_EQ(startup_refusal("[can]\nuri = \"socketcan:gvsnone0\"\n"), "(accepted)");
  EXPECT_EQ(startup_refusal("[source]\nuri = \"libcamera:0\"\n"), "(accepted)");
  EXPECT_EQ(startup_refusal("[light]\ndriver = \"gpio\"\nchip = \"/nonexistent/gpiochip9\"\nled_line = 3\n"),
            "(accepted)");
  EXPECT_EQ(check_startup(DaemonConfig{}), "gvs");
}

}  // namespace
}  // namespace gvs::daemon
