// lrd-slam's YAML config (strict: unknown keys, wrong types and ranges are errors with FILE:LINE).
#include "fuzz_input.h"
#include "lrd/config/config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const std::string text(reinterpret_cast<const char*>(data), size);
  return guarded([&] { (void)lrd::config::load_config_text(text, "fuzz.yaml"); });
}
