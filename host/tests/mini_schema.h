// host/tests/mini_schema.h - the schemas' test validator, shared by the tests of the files they
// describe (test_robot_file.cpp, physics/tests/test_cell_file.cpp).
#ifndef ARTICULA_HOST_TESTS_MINI_SCHEMA_H
#define ARTICULA_HOST_TESTS_MINI_SCHEMA_H

#include <nlohmann/json.hpp>

#include <cmath>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace articula::test {

using json = nlohmann::json;

// A validator for the part of JSON Schema 2020-12 that the project's schemas use (robots/,
// scenes/, cells/). A keyword it
// does not know is an error, so the schema cannot grow past what this test checks.
class MiniSchema {
 public:
  explicit MiniSchema(const json& root) : root_(root) {}

  std::vector<std::string> errors(const json& doc) const {
    std::vector<std::string> out;
    check(root_, doc, "", out);
    return out;
  }

 private:
  bool valid(const json& s, const json& v) const {
    std::vector<std::string> e;
    check(s, v, "", e);
    return e.empty();
  }

  static bool has_type(const json& v, const std::string& t) {
    if (t == "object") return v.is_object();
    if (t == "array") return v.is_array();
    if (t == "string") return v.is_string();
    if (t == "boolean") return v.is_boolean();
    if (t == "null") return v.is_null();
    if (t == "number") return v.is_number();
    if (t == "integer") return v.is_number() && std::floor(v.get<double>()) == v.get<double>();
    throw std::logic_error("unknown type " + t);
  }

  void check(const json& s, const json& v, const std::string& path, std::vector<std::string>& out) const {
    static const std::set<std::string> known = {
        "$schema", "$id", "title", "description", "$comment", "default", "$defs",  // annotations
        "$ref", "type", "properties", "additionalProperties", "required", "items", "minItems", "maxItems",
        "minimum", "maximum", "exclusiveMinimum", "minLength", "enum", "const", "oneOf", "allOf", "not", "if",
        "then", "else", "pattern"};
    if (s.is_boolean()) {
      if (!s.get<bool>()) out.push_back(path + ": not allowed");
      return;
    }
    for (const auto& kw : s.items())
      if (!known.count(kw.key())) throw std::logic_error("schema keyword the test does not implement: " + kw.key());
    auto err = [&](const std::string& m) { out.push_back(path + ": " + m); };

    if (s.contains("$ref")) {
      const std::string ref = s["$ref"];
      if (ref.rfind("#/", 0) != 0) throw std::logic_error("only local $ref: " + ref);
      check(root_.at(json::json_pointer(ref.substr(1))), v, path, out);
    }
    if (s.contains("type") && !has_type(v, s["type"])) err("not of type " + s["type"].get<std::string>());
    if (s.contains("enum")) {
      bool found = false;
      for (const json& e : s["enum"]) found = found || e == v;
      if (!found) err("not one of " + s["enum"].dump());
    }
    if (s.contains("const") && s["const"] != v) err("not " + s["const"].dump());
    if (v.is_object()) {
      const json empty = json::object();
      const json& props = s.contains("properties") ? s["properties"] : empty;
      for (const auto& item : v.items()) {
        const std::string p = path + "/" + item.key();
        if (props.contains(item.key()))
          check(props[item.key()], item.value(), p, out);
        else if (s.contains("additionalProperties"))
          check(s["additionalProperties"], item.value(), p, out);
      }
      if (s.contains("required"))
        for (const json& k : s["required"])
          if (!v.contains(k.get<std::string>())) err("missing " + k.get<std::string>());
    }
    if (v.is_array()) {
      if (s.contains("items"))
        for (std::size_t i = 0; i < v.size(); ++i) check(s["items"], v[i], path + "/" + std::to_string(i), out);
      if (s.contains("minItems") && v.size() < s["minItems"].get<std::size_t>()) err("too few items");
      if (s.contains("maxItems") && v.size() > s["maxItems"].get<std::size_t>()) err("too many items");
    }
    if (v.is_number()) {
      const double x = v.get<double>();
      if (s.contains("minimum") && x < s["minimum"].get<double>()) err("below minimum");
      if (s.contains("maximum") && x > s["maximum"].get<double>()) err("above maximum");
      if (s.contains("exclusiveMinimum") && x <= s["exclusiveMinimum"].get<double>()) err("not above exclusiveMinimum");
    }
    if (v.is_string() && s.contains("minLength") && v.get<std::string>().size() < s["minLength"].get<std::size_t>())
      err("too short");
    if (v.is_string() && s.contains("pattern") &&
        !std::regex_search(v.get<std::string>(), std::regex(s["pattern"].get<std::string>(), std::regex::ECMAScript)))
      err("does not match " + s["pattern"].get<std::string>());
    if (s.contains("allOf"))
      for (const json& sub : s["allOf"]) check(sub, v, path, out);
    if (s.contains("oneOf")) {
      int n = 0;
      for (const json& sub : s["oneOf"]) n += valid(sub, v) ? 1 : 0;
      if (n != 1) err("matches " + std::to_string(n) + " of oneOf");
    }
    if (s.contains("not") && valid(s["not"], v)) err("matches \"not\"");
    if (s.contains("if")) {
      if (valid(s["if"], v)) {
        if (s.contains("then")) check(s["then"], v, path, out);
      } else if (s.contains("else")) {
        check(s["else"], v, path, out);
      }
    }
  }

  const json& root_;
};

}  // namespace articula::test

#endif  // ARTICULA_HOST_TESTS_MINI_SCHEMA_H
