#include "twin/batch/batch_manifest.h"

#include <filesystem>
#include <set>
#include <stdexcept>

#include "twin/base/json_field.h"
#include "twin/trials/identification.h"

namespace twin::batch {
namespace {

namespace fs = std::filesystem;

std::string resolve(const std::string& path, const std::string& base_directory) {
  const fs::path p(path);
  return p.is_absolute() || base_directory.empty() ? path : (fs::path(base_directory) / p).string();
}

std::vector<std::string> directories(const JsonField& f, const std::string& base_directory) {
  if (!f.is_array() || f.array_size() == 0) f.fail("must list at least one trial directory");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < f.array_size(); ++i) {
    const std::string dir = resolve(f[i].string(), base_directory);
    if (!fs::is_directory(dir)) f[i].fail("names no directory: " + dir);
    out.push_back(dir);
  }
  return out;
}

bool valid_name(const std::string& name) {
  if (name.empty() || name == "." || name == ".." || name.size() > 100) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

void read_diagnose_options(const JsonField& f, diagnosis::DiagnoseOptions& o) {
  f.only_keys({"triangles", "path_triangles", "refits", "effects", "noise_mm", "optimizer", "discretisation_check"});
  auto integer_in = [](const JsonField& v, long long lo, long long hi) {
    if (!v.json().is_number_integer() || v.json().get<long long>() < lo || v.json().get<long long>() > hi) {
      v.fail("must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    }
    return v.json().get<int>();
  };
  if (auto v = f.optional("triangles")) o.triangles = integer_in(*v, 50, 200000);
  if (auto v = f.optional("path_triangles")) o.path_triangles = integer_in(*v, 0, 200000);
  if (auto v = f.optional("refits")) o.refits = integer_in(*v, 1, 10);
  if (auto v = f.optional("effects")) o.effects = v->string();
  if (auto v = f.optional("noise_mm")) o.noise_mm = v->positive("mm");
  if (auto v = f.optional("optimizer")) {
    const std::string name = v->string();
    if (name != "lm" && name != "lbfgs") v->fail("must be \"lm\" or \"lbfgs\"");
    o.optimizer = optimizer_from_name(name);
  }
  if (auto v = f.optional("discretisation_check")) {
    if (!v->json().is_boolean()) v->fail("must be true or false");
    o.discretisation_check = v->json().get<bool>();
  }
}

}  // namespace

BatchManifest batch_manifest_from_json(const nlohmann::json& j, const std::string& source,
                                       const std::string& base_directory) {
  const JsonField root(j, source);
  if (!root.is_object()) root.fail("must be a JSON object");
  root.only_keys({"materials", "diagnose"});
  BatchManifest m;
  m.source = source;
  if (auto d = root.optional("diagnose")) {
    if (!d->is_object()) d->fail("must be an object");
    read_diagnose_options(*d, m.diagnose);
  }
  const JsonField list = root["materials"];
  if (!list.is_array() || list.array_size() == 0) list.fail("must list at least one material");
  std::set<std::string> names;
  const nlohmann::json options_json = root.has("diagnose") ? j["diagnose"] : nlohmann::json::object();
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    const JsonField e = list[i];
    if (!e.is_object()) e.fail("must be an object with name, train and test");
    e.only_keys({"name", "train", "test", "material"});
    BatchMaterial b;
    b.name = e["name"].string();
    if (!valid_name(b.name)) {
      e["name"].fail("must be 1-100 letters, digits, '.', '_' or '-' (it names the output directory), not \"" +
                     b.name + "\"");
    }
    if (!names.insert(b.name).second) e["name"].fail("repeats the material \"" + b.name + "\"");
    b.train = directories(e["train"], base_directory);
    b.test = directories(e["test"], base_directory);
    if (auto v = e.optional("material")) {
      b.material = resolve(v->string(), base_directory);
      if (!fs::is_regular_file(b.material)) v->fail("names no file: " + b.material);
    }
    nlohmann::json fingerprint = {{"name", b.name}, {"train", b.train}, {"test", b.test}, {"material", b.material},
                                  {"diagnose", options_json}};
    b.fingerprint = fingerprint.dump();
    m.materials.push_back(std::move(b));
  }
  return m;
}

BatchManifest read_batch_manifest(const std::string& path) {
  const nlohmann::json j = JsonField::parse_file(path);
  return batch_manifest_from_json(j, path, fs::path(path).parent_path().string());
}

}  // namespace twin::batch
