#pragma once
// Validated reading of one JSON object of a scene file. Every access names the key, its unit and its
// allowed range; finish() rejects keys that were never read (unknown keys, typos), naming the nearest allowed
// key. A misspelt key is the user's mistake and is reported first: a required key that is missing while a
// misspelling of it is present is reported as that unknown key, and so is any other problem found while the
// object holds a misspelling of a key the reader looked for and did not find (its default then stood in for
// the value meant). All problems are InputError messages of the form "<file>: key '<path>': <what is wrong>;
// <what is allowed>".

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// One setting as a reader took it (the value in the file, or the default), with what is allowed: lets a UI
/// offer a block's settings for editing without knowing whose block it is (the viewer's panel).
struct JsonField {
  enum class Kind { number, integer, boolean, string };
  std::string key;  ///< full key path, e.g. "implicit.max_cg_iterations"
  Kind kind = Kind::number;
  double value = 0.0, lo = 0.0, hi = 0.0;  ///< number, integer (boolean: 0 or 1)
  std::string text;                        ///< string
  std::vector<std::string> allowed;        ///< string: the choices (empty: any)
};

class JsonReader {
 public:
  /// `object` must outlive the reader. `path` is the key path of the object ("" for the root).
  JsonReader(const nlohmann::json& object, std::string path, std::string file);

  /// Whether the object holds `key` (a key asked about is one the reader knows: a key present one edit from
  /// it, while it is absent, is its misspelling).
  bool has(const std::string& key) const;
  /// A number in [lo, hi] (inclusive), default when absent.
  double number(const std::string& key, double fallback, double lo, double hi);
  /// A number that must be present.
  double required_number(const std::string& key, double lo, double hi);
  int integer(const std::string& key, int fallback, int lo, int hi);
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed = {});
  std::string required_string(const std::string& key, const std::vector<std::string>& allowed = {});
  /// Three finite numbers [x, y, z].
  Vec3 vec3(const std::string& key, const Vec3& fallback);
  Vec3 required_vec3(const std::string& key);
  /// A nested object (must be an object if present); absent: an empty object, whose problems are reported as
  /// this object's misspelling of `key` when it holds one (a required key missing from a block typed under
  /// another name).
  JsonReader object(const std::string& key);
  /// A required array of objects.
  std::vector<JsonReader> array_of_objects(const std::string& key, bool required);
  /// The raw value (marks the key as read).
  const nlohmann::json* raw(const std::string& key);

  /// Keys this object also accepts on paths not taken (the other of two alternatives, a block read only when
  /// present): finish() lists them as allowed, and a required key's check never takes them for its
  /// misspelling.
  void allow(std::initializer_list<const char*> keys);
  /// Throws for a required `key` that is absent: "missing; <what>" (e.g. "a number in [0, 1] is required"),
  /// or, when the object holds an unread key that is a misspelling of it, that key as unknown with `key` to
  /// use (and as fail() does, a misspelling of another key).
  [[noreturn]] void missing(const std::string& key, const std::string& what) const;

  /// Throws for keys present in the object that were never read, naming the nearest allowed key; a key
  /// misspelt from one the reader looked for and did not find first (of "tye" and "direction" in a block
  /// whose "type" defaulted to one without a direction, "tye").
  void finish() const;
  /// From now on every number, integer, boolean and string this reader (and the objects it opens) takes is
  /// appended to `fields`, which must outlive them (nullptr: stop).
  void record_fields(std::vector<JsonField>* fields) { fields_ = fields; }

  /// Throws "<file>: key '<path.key>': <message>"; when the object holds a misspelling of a key the reader
  /// looked for and did not find (or the object is absent because its own key was misspelt), that unknown key
  /// first: "<file>: key '<typed>': unknown key (did you mean '<meant>'?); without '<meant>': key ...".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  std::string key_path(const std::string& key) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

 private:
  /// A key typed in the file (its full path) and the key the reader knows that it misspells.
  struct Misspelling {
    std::string typed_path, meant;
  };
  const nlohmann::json* find(const std::string& key);
  void note(const std::string& key, JsonField field);
  /// A present key nothing has read, may read or asked about, one edit from a key the reader read, allowed or
  /// asked about that is absent; else the misspelling that left this object absent.
  std::optional<Misspelling> misspelling() const;
  /// The present key nothing has read, may read or asked about that is nearest to `key` within a few edits.
  std::optional<std::string> misspelling_of(const std::string& key) const;
  /// Throws `problem` ("key '<path>': ..."), after the misspelling that probably caused it when there is one.
  [[noreturn]] void report(const std::string& problem) const;
  const nlohmann::json& object_;
  std::string path_, file_;
  std::set<std::string> read_, allowed_;  // keys read; keys accepted but not read on this path
  mutable std::set<std::string> asked_;   // keys has() was asked about
  std::optional<Misspelling> absent_as_;  // this object is absent: its key is misspelt so in the parent
  std::vector<JsonField>* fields_ = nullptr;
};

}  // namespace vascsim
