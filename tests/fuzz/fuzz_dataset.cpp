// libFuzzer target: the dataset reader (camera.json, frames.csv, truth.csv
// of a gvs-dataset folder). The first input byte picks the file the rest of
// the input replaces; the other two are valid. Any content must be read or
// refused with a DatasetError naming the file; anything else is a finding.
#include <cstddef>
#include <climits>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

#include "gvs/drivers/dataset.hpp"

namespace {

constexpr std::string_view kCamera =
    R"({"format":"gvs-dataset/1","width":64,"height":48,"mm_per_px":0.1,"mount_yaw_deg":0.0})";
constexpr std::string_view kFrames =
    "index,file,t_ns,exposure_us,pulses\n0,frames/000000.png,0,3000,\n1,frames/000001.png,16666667,3000,0:20|400:20\n";
constexpr std::string_view kTruth =
    "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps\n0,1500000,1,0,1,0,0\n1,18166667,1,0,1,0,0\n";

void write(const std::filesystem::path& p, std::string_view text) {
  std::ofstream(p, std::ios::binary).write(text.data(), static_cast<std::streamsize>(text.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("gvs_fuzz_dataset_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string_view input(reinterpret_cast<const char*>(data) + 1, size - 1);
  const int which = data[0] % 3;
  write(dir / "camera.json", which == 0 ? input : kCamera);
  write(dir / "frames.csv", which == 1 ? input : kFrames);
  write(dir / "truth.csv", which == 2 ? input : kTruth);
  try {
    const gvs::drivers::DatasetReader reader(dir);
    if (reader.camera().geometry.width_px <= 0 || reader.camera().geometry.height_px <= 0) __builtin_trap();
    std::int64_t previous = INT64_MIN;
    for (const auto& f : reader.frames()) {
      if (!(f.exposure.exposure_us > 0.0) || f.t_ns < previous) __builtin_trap();
      previous = f.t_ns;
    }
  } catch (const gvs::drivers::DatasetError&) {
  }
  return 0;
}
