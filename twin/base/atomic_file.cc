#include "twin/base/atomic_file.h"

#include <fstream>
#include <iomanip>
#include <limits>
#include <locale>
#include <stdexcept>

namespace twin {

namespace fs = std::filesystem;

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& body) {
  fs::path tmp = path;
  tmp += ".tmp";
  std::error_code ignored;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open " + tmp.string());
    out.imbue(std::locale::classic());
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    try {
      body(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ignored);
      throw;
    }
    out.close();
    if (!out) {
      fs::remove(tmp, ignored);
      throw std::runtime_error(path.string() + ": writing " + tmp.string() + " failed");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ignored);
    throw std::runtime_error(path.string() + ": cannot rename " + tmp.string() + ": " +
                             ec.message());
  }
}


}  // namespace twin
