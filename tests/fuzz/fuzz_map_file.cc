// Map files (.lrdmap). The input is the file without its trailing checksum, which the harness
// appends, so the search reaches the sections behind it (a wrong checksum is refused first).
#include "fuzz_input.h"
#include "lrd/map/map.h"
#include "lrd/map/map_file.h"
#include "lrd/util/binary_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::uint64_t sum = lrd::util::fnv1a64(bytes);
  for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<char>((sum >> (8 * i)) & 0xff));
  const auto file = write_input("map.lrdmap", bytes);
  return guarded([&] {
    lrd::map::Map map;
    (void)lrd::map::load_map_file(file, map);
  });
}
