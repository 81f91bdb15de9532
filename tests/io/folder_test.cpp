// list_json_files: the *.json regular files of a folder, sorted; a missing folder is an input error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "io/folder.hpp"
#include "uavcover/error.hpp"

namespace fs = std::filesystem;

TEST(ListJsonFiles, SortedRegularJsonFilesOnly) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover-folder-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub.json");
  for (const char* name : {"b.json", "a.json", "notes.txt", "c.json.bak"}) std::ofstream(dir / name) << "{}";
  std::ofstream(dir / "sub.json" / "inner.json") << "{}";
  const auto files = uavcover::io::list_json_files(dir, "--seed-dir");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].filename(), "a.json");
  EXPECT_EQ(files[1].filename(), "b.json");
  try {
    (void)uavcover::io::list_json_files(dir / "missing", "--seed-dir");
    ADD_FAILURE() << "no error for a missing folder";
  } catch (const uavcover::InputError& e) {
    EXPECT_EQ(e.field(), "--seed-dir");
  }
  EXPECT_THROW((void)uavcover::io::list_json_files(dir / "a.json", "--seed-dir"), uavcover::InputError);
  fs::remove_all(dir);
}
