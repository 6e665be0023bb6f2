// Bag-of-words vocabularies (.lrdv).
#include "fuzz_input.h"
#include "lrd/place/vocabulary.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const auto file = write_input("vocab.lrdv", {reinterpret_cast<const char*>(data), size});
  return guarded([&] { (void)lrd::place::Vocabulary::load(file); });
}
