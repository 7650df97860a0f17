#include "vascsim/core/json_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <array>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/core/text.hpp"

namespace vascsim {

namespace {
const nlohmann::json& empty_object() {
  static const nlohmann::json e = nlohmann::json::object();
  return e;
}

JsonField numeric_field(JsonField::Kind kind, double value, double lo, double hi) {
  JsonField f;
  f.kind = kind;
  f.value = value;
  f.lo = lo;
  f.hi = hi;
  return f;
}

std::string type_name(const nlohmann::json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "null";
}
}  // namespace

JsonReader::JsonReader(const nlohmann::json& object, std::string path, std::string file)
    : object_(object), path_(std::move(path)), file_(std::move(file)) {
  if (!object_.is_object())
    throw InputError(fmt::format("{}: key '{}': expected an object, found {}", file_,
                                 path_.empty() ? "(root)" : path_, type_name(object_)));
}

std::string JsonReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonReader::fail(const std::string& key, const std::string& message) const {
  report(fmt::format("key '{}': {}", key_path(key), message));
}

std::optional<JsonReader::Misspelling> JsonReader::misspelling() const {
  // The keys the reader looked for (read, allowed or asked about) that the object lacks: a present key it
  // knows nothing of one edit from one of them (a letter dropped, added or changed, two neighbours swapped)
  // is that key misspelt, and its default stood in for the value meant. One edit, not nearest_name's few: a
  // key the reader has not reached yet may be two from one it has (min_newton_iterations after
  // max_newton_iterations).
  const auto known = [&](const std::string& k) {
    return read_.count(k) > 0 || allowed_.count(k) > 0 || asked_.count(k) > 0;
  };
  for (const auto& [k, v] : object_.items()) {
    if (known(k)) continue;
    for (const std::set<std::string>* looked_for :
         std::array<const std::set<std::string>*, 3>{&read_, &allowed_, &asked_})
      for (const std::string& t : *looked_for)
        if (!object_.contains(t) && edit_distance(k, t) == 1) return Misspelling{key_path(k), t};
  }
  return absent_as_;
}

void JsonReader::report(const std::string& problem) const {
  if (const std::optional<Misspelling> m = misspelling())
    throw InputError(fmt::format("{}: key '{}': unknown key (did you mean '{}'?); without '{}': {}", file_,
                                 m->typed_path, m->meant, m->meant, problem));
  throw InputError(fmt::format("{}: {}", file_, problem));
}

bool JsonReader::has(const std::string& key) const {
  asked_.insert(key);
  return object_.contains(key);
}

const nlohmann::json* JsonReader::find(const std::string& key) {
  read_.insert(key);
  auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

const nlohmann::json* JsonReader::raw(const std::string& key) {
  return find(key);
}

void JsonReader::note(const std::string& key, JsonField field) {
  if (fields_ == nullptr) return;
  field.key = key_path(key);
  fields_->push_back(std::move(field));
}

double JsonReader::number(const std::string& key, double fallback, double lo, double hi) {
  const auto* v = find(key);
  double x = fallback;
  if (v) {
    if (!v->is_number())
      fail(key, fmt::format("expected a number in [{}, {}], found {}", lo, hi, type_name(*v)));
    x = v->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      fail(key, fmt::format("value {} is out of range; allowed [{}, {}]", x, lo, hi));
  }
  note(key, numeric_field(JsonField::Kind::number, x, lo, hi));
  return x;
}

double JsonReader::required_number(const std::string& key, double lo, double hi) {
  if (!has(key)) missing(key, fmt::format("a number in [{}, {}] is required", lo, hi));
  return number(key, 0.0, lo, hi);
}

int JsonReader::integer(const std::string& key, int fallback, int lo, int hi) {
  const auto* v = find(key);
  int n = fallback;
  if (v) {
    if (!v->is_number_integer() && !(v->is_number() && std::floor(v->get<double>()) == v->get<double>()))
      fail(key, fmt::format("expected an integer in [{}, {}], found {}", lo, hi,
                            v->is_number() ? fmt::format("{}", v->get<double>()) : type_name(*v)));
    const double x = v->get<double>();
    if (x < lo || x > hi) fail(key, fmt::format("value {} is out of range; allowed [{}, {}]", x, lo, hi));
    n = static_cast<int>(x);
  }
  note(key, numeric_field(JsonField::Kind::integer, n, lo, hi));
  return n;
}

bool JsonReader::boolean(const std::string& key, bool fallback) {
  const auto* v = find(key);
  bool b = fallback;
  if (v) {
    if (!v->is_boolean()) fail(key, fmt::format("expected true or false, found {}", type_name(*v)));
    b = v->get<bool>();
  }
  note(key, numeric_field(JsonField::Kind::boolean, b ? 1.0 : 0.0, 0.0, 1.0));
  return b;
}

std::string JsonReader::string(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& allowed) {
  const auto* v = find(key);
  std::string s = fallback;
  if (v) {
    const std::string choices = allowed.empty() ? "" : fmt::format("; allowed: {}", fmt::join(allowed, ", "));
    if (!v->is_string()) fail(key, fmt::format("expected a string, found {}{}", type_name(*v), choices));
    s = v->get<std::string>();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end())
      fail(key, fmt::format("unknown value '{}'{}", s, choices));
  }
  JsonField field;
  field.kind = JsonField::Kind::string;
  field.text = s;
  field.allowed = allowed;
  note(key, std::move(field));
  return s;
}

std::string JsonReader::required_string(const std::string& key, const std::vector<std::string>& allowed) {
  if (!has(key))
    missing(key,
            allowed.empty() ? "a string is required" : fmt::format("one of: {}", fmt::join(allowed, ", ")));
  return string(key, "", allowed);
}

Vec3 JsonReader::vec3(const std::string& key, const Vec3& fallback) {
  const auto* v = find(key);
  if (!v) return fallback;
  if (!v->is_array() || v->size() != 3) fail(key, "expected an array of 3 numbers [x, y, z]");
  Vec3 out;
  for (int a = 0; a < 3; ++a) {
    const auto& e = (*v)[static_cast<std::size_t>(a)];
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      fail(key, "expected an array of 3 finite numbers [x, y, z]");
    out[a] = e.get<double>();
  }
  return out;
}

Vec3 JsonReader::required_vec3(const std::string& key) {
  if (!has(key)) missing(key, "an array of 3 numbers [x, y, z] is required");
  return vec3(key, Vec3::Zero());
}

JsonReader JsonReader::object(const std::string& key) {
  const auto* v = find(key);
  if (v && !v->is_object()) fail(key, fmt::format("expected an object, found {}", type_name(*v)));
  JsonReader child(v ? *v : empty_object(), key_path(key), file_);
  child.fields_ = fields_;
  if (!v) {
    // An absent block typed under another name: its problems (a required key missing) are that name's.
    if (const std::optional<std::string> typo = misspelling_of(key))
      child.absent_as_ = Misspelling{key_path(*typo), key};
    else
      child.absent_as_ = absent_as_;
  }
  return child;
}

std::vector<JsonReader> JsonReader::array_of_objects(const std::string& key, bool required) {
  const auto* v = find(key);
  std::vector<JsonReader> out;
  if (!v) {
    if (required) missing(key, "an array of objects is required");
    return out;
  }
  if (!v->is_array()) fail(key, fmt::format("expected an array of objects, found {}", type_name(*v)));
  for (std::size_t i = 0; i < v->size(); ++i) {
    const auto& e = (*v)[i];
    const std::string p = fmt::format("{}.{}", key_path(key), i);
    if (!e.is_object())
      throw InputError(fmt::format("{}: key '{}': expected an object, found {}", file_, p, type_name(e)));
    out.emplace_back(e, p, file_);
  }
  return out;
}

void JsonReader::allow(std::initializer_list<const char*> keys) {
  for (const char* k : keys) allowed_.insert(k);
}

std::optional<std::string> JsonReader::misspelling_of(const std::string& key) const {
  // The keys present that nothing has read, may read or asked about: the one closest to `key` (within
  // nearest_name's few edits) is its misspelling.
  std::optional<std::string> typo;
  for (const auto& [k, v] : object_.items())
    if (k != key && !read_.count(k) && !allowed_.count(k) && !asked_.count(k) && nearest_name(k, {key}) &&
        (!typo || edit_distance(k, key) < edit_distance(*typo, key)))
      typo = k;
  return typo;
}

void JsonReader::missing(const std::string& key, const std::string& what) const {
  // A misspelling is the user's actual mistake, so it is named first (else the message names only a key the
  // file never held): one edit from `key` or from another key the reader looked for (the alternative `key`
  // stands for, z_center_m for s_center_m; a key whose default made `key` required), else a few from `key`.
  const std::optional<Misspelling> near = misspelling();
  if (near && near->meant != key) fail(key, "missing; " + what);
  std::optional<std::string> typed_path = near ? std::optional<std::string>(near->typed_path) : std::nullopt;
  if (!typed_path)
    if (const std::optional<std::string> typo = misspelling_of(key)) typed_path = key_path(*typo);
  if (typed_path)
    throw InputError(fmt::format("{}: key '{}': unknown key (did you mean '{}'?); '{}' is missing: {}", file_,
                                 *typed_path, key, key, what));
  fail(key, "missing; " + what);
}

void JsonReader::finish() const {
  std::set<std::string> known_set = read_;
  known_set.insert(allowed_.begin(), allowed_.end());
  const std::vector<std::string> known(known_set.begin(), known_set.end());
  // Of the keys never read (an allowed key that is present is read, or rejected with its own message before),
  // a misspelling of a key the object lacks first: its default may be what made the others unknown (a "tye"
  // left a region's bc "probe", which takes no "direction").
  std::optional<std::string> first, first_near;
  for (const auto& [k, v] : object_.items()) {
    if (read_.count(k)) continue;
    const std::optional<std::string> near = nearest_name(k, known);
    if (!first) first = k, first_near = near;
    if (near && !object_.contains(*near)) {
      first = k, first_near = near;
      break;
    }
  }
  if (first)
    throw InputError(
        fmt::format("{}: key '{}': unknown key{}{}", file_, key_path(*first),
                    first_near ? fmt::format(" (did you mean '{}'?)", *first_near) : "",
                    known.empty() ? "" : fmt::format("; allowed here: {}", fmt::join(known, ", "))));
}

}  // namespace vascsim
