// The shared durable writer (common/durable_file.h) and append journal (common/append_journal.h):
// a write that fails anywhere leaves the old file as it was and says which file and why.
// The failures are made so that they happen for root too (CI runs as root, for whom a read-only
// directory is still writable): the temporary's name taken by a directory, a disk that is full
// (/dev/full), a body that throws halfway.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "common/append_journal.h"
#include "common/durable_file.h"
#include "tests/support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the durable writer replaces a file whole and leaves no temporary", "[durable_file]") {
  testing_support::TempDir dir("durable_replace");
  const fs::path file = dir / "material.json";
  prepreg::write_file_atomically(file, [](std::ostream& out) { out << 0.1 << " old\n"; });
  CHECK(contents(file) == "0.10000000000000001 old\n");  // max_digits10, classic locale
  const std::string big(300000, 'x');                    // more than the writer's buffer
  prepreg::write_file_atomically(file, big);
  CHECK(contents(file) == big);
  CHECK_FALSE(fs::exists(dir / "material.json.tmp"));
}

TEST_CASE("a failed durable write leaves the old file intact and names the file", "[durable_file]") {
  testing_support::TempDir dir("durable_fail");
  const fs::path file = dir / "trial.json";
  const fs::path tmp = dir / "trial.json.tmp";
  prepreg::write_file_atomically(file, std::string("old contents\n"));

  SECTION("the temporary cannot be created (its name is a directory)") {
    fs::create_directories(tmp / "occupied");
    const std::string error = error_of([&] { prepreg::write_file_atomically(file, std::string("new\n")); });
    CHECK_THAT(error, Catch::Contains(file.string()) && Catch::Contains("cannot open"));
    CHECK(fs::is_directory(tmp));  // not the writer's to remove
  }
  SECTION("the disk is full") {
    fs::create_symlink("/dev/full", tmp);  // the writer opens the temporary through it
    const std::string error = error_of([&] { prepreg::write_file_atomically(file, std::string(100000, 'y')); });
    CHECK_THAT(error, Catch::Contains(file.string()) && Catch::Contains("No space left on device"));
    CHECK_FALSE(fs::exists(fs::symlink_status(tmp)));  // the failed temporary is removed
  }
  SECTION("the body throws halfway") {
    const std::string error = error_of([&] {
      prepreg::write_file_atomically(file, [](std::ostream& out) {
        out << std::string(200000, 'z');
        throw std::runtime_error("body failed");
      });
    });
    CHECK(error == "body failed");
    CHECK_FALSE(fs::exists(tmp));
  }
  SECTION("the directory is gone") {
    const fs::path elsewhere = dir / "missing" / "trial.json";
    CHECK_THAT(error_of([&] { prepreg::write_file_atomically(elsewhere, std::string("new\n")); }),
               Catch::Contains(elsewhere.string()) && Catch::Contains("No such file or directory"));
  }
  CHECK(contents(file) == "old contents\n");
}

TEST_CASE("directories are created durably, and errors name the directory", "[durable_file]") {
  testing_support::TempDir dir("durable_dirs");
  prepreg::create_directories_durably(dir / "a" / "b" / "c");
  CHECK(fs::is_directory(dir / "a" / "b" / "c"));
  prepreg::create_directories_durably(dir / "a" / "b" / "c");  // already there: nothing to do
  prepreg::write_file_atomically(dir / "plain", std::string("x"));
  CHECK_THAT(error_of([&] { prepreg::create_directories_durably(dir / "plain" / "sub"); }),
             Catch::Contains((dir / "plain" / "sub").string()));
  CHECK_THAT(error_of([&] { prepreg::sync_directory(dir / "nowhere"); }), Catch::Contains((dir / "nowhere").string()));
}

TEST_CASE("the append journal keeps every record and names its file on failure", "[durable_file]") {
  testing_support::TempDir dir("durable_journal");
  {
    prepreg::AppendJournal journal(dir / "index.txt");
    journal.append("# header\n");
    journal.append("1 2 3\n");
  }
  CHECK(contents(dir / "index.txt") == "# header\n1 2 3\n");
  CHECK_THAT(error_of([&] { prepreg::AppendJournal(dir / "missing" / "index.txt"); }),
             Catch::Contains((dir / "missing" / "index.txt").string()));
  fs::create_symlink("/dev/full", dir / "full.txt");
  prepreg::AppendJournal full(dir / "full.txt");
  CHECK_THAT(error_of([&] { full.append("1 2 3\n"); }),
             Catch::Contains((dir / "full.txt").string()) && Catch::Contains("No space left on device"));
}
