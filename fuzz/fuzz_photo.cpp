// libFuzzer target: the photo metadata reader (io::read_photo_tags, exiv2, issue 32) on untrusted bytes:
// any file is read or refused with an InputError naming the photo or its tag; never a crash, a hang or
// another exception.
#include <cstddef>
#include <cstdint>

#include "io/exif.hpp"
#include "uavcover/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)uavcover::io::read_photo_tags(data, size, "photo.jpg");
  } catch (const uavcover::InputError&) {
    // refused, naming the field: the wanted outcome for bad input
  }
  return 0;
}
