// Python keywords from the library's parameter structs: conversion of each
// member type (numbers, bools, enums, lengths), the keyword table of a struct
// (ParamTable, generated from the header by extract_docs.py), kwargs -> struct,
// and the docstring part listing every keyword with its default and doc.
#pragma once

#include <pybind11/pybind11.h>

#include <cctype>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "header_docs.h"
#include "module.h"

namespace detexture::python {

inline std::string normalized(const std::string& name) {
  std::string out;
  for (char c : name)
    if (c != '-' && c != '_') out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

template <class T>
std::string type_name() {
  if constexpr (std::is_same_v<T, Length>)
    return "length";
  else if constexpr (std::is_same_v<T, bool>)
    return "bool";
  else if constexpr (std::is_floating_point_v<T>)
    return "float";
  else if constexpr (std::is_integral_v<T>)
    return "int";
  else
    return py::type::of<T>().attr("__name__").template cast<std::string>();
}

template <class T>
py::object to_py(const T& value) {
  if constexpr (std::is_same_v<T, Length>)
    return py::str(to_string(value));
  else
    return py::cast(value);
}

template <class T>
void from_py(T& out, py::handle h, const std::string& keyword) {
  const std::string got = py::repr(h).cast<std::string>();
  if constexpr (std::is_same_v<T, Length>) {
    // "0.05", "0.02d", "0.5r", "1.5t", "auto", or a number in the cloud's units.
    if (py::isinstance<py::str>(h)) {
      out = parse_length(h.cast<std::string>());
    } else if (py::isinstance<py::float_>(h) || py::isinstance<py::int_>(h)) {
      if (py::isinstance<py::bool_>(h))
        throw py::type_error(keyword + " must be a length, got " + got);
      out = Length{h.cast<double>(), Length::Unit::Absolute};
    } else {
      throw py::type_error(keyword +
                           " must be a length (a number, or a string such as '0.02d', "
                           "'0.5r', '1.5t'), got " +
                           got);
    }
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!py::isinstance<py::bool_>(h))
      throw py::type_error(keyword + " must be True or False, got " + got);
    out = h.cast<bool>();
  } else if constexpr (std::is_enum_v<T>) {
    if (py::isinstance<py::str>(h)) {
      const std::string want = normalized(h.cast<std::string>());
      const py::dict members = py::type::of<T>().attr("__members__");
      std::string names;
      for (const auto& item : members) {
        const std::string n = py::cast<std::string>(item.first);
        if (normalized(n) == want) {
          out = py::cast<T>(item.second);
          return;
        }
        names += (names.empty() ? "" : ", ") + n;
      }
      throw py::value_error(keyword + " must be one of " + names + ", got " + got);
    }
    try {
      out = h.cast<T>();
    } catch (const py::cast_error&) {
      throw py::type_error(keyword + " must be a " + type_name<T>() + " or its name, got " + got);
    }
  } else {
    if (py::isinstance<py::bool_>(h) || (std::is_integral_v<T> && !py::isinstance<py::int_>(h)) ||
        !(py::isinstance<py::int_>(h) || py::isinstance<py::float_>(h)))
      throw py::type_error(keyword + " must be " + (std::is_integral_v<T> ? "an int" : "a number") +
                           ", got " + got);
    try {
      out = h.cast<T>();
    } catch (const py::cast_error&) {
      throw py::value_error(keyword + " is out of range: " + got);
    }
  }
}

template <class Params>
struct ParamField {
  std::string keyword, doc_key, type;
  bool is_enum = false;
  std::function<py::object(const Params&)> get;
  std::function<void(Params&, py::handle)> set;
};

/// The keywords of Params, in struct order (ParamTable<Params>, generated).
template <class Params>
const std::vector<ParamField<Params>>& param_fields() {
  static const std::vector<ParamField<Params>> fields = [] {
    std::vector<ParamField<Params>> out;
    ParamTable<Params>::for_each([&](const char* keyword, const char* key, auto access) {
      using T = std::decay_t<decltype(access(std::declval<Params&>()))>;
      ParamField<Params> f{keyword, key, type_name<T>(), std::is_enum_v<T>, {}, {}};
      f.get = [access](const Params& p) { return to_py(access(const_cast<Params&>(p))); };
      f.set = [access, k = std::string(keyword)](Params& p, py::handle h) {
        from_py(access(p), h, k);
      };
      out.push_back(std::move(f));
    });
    return out;
  }();
  return fields;
}

/// Params from keyword arguments (defaults for the rest). Keywords in
/// `others` are left to the caller; any other unknown one is a TypeError
/// naming `function`.
template <class Params>
Params params_from_kwargs(const py::kwargs& kwargs, const std::string& function,
                          const std::set<std::string>& others = {}) {
  static const std::map<std::string, const ParamField<Params>*> by_keyword = [] {
    std::map<std::string, const ParamField<Params>*> m;
    for (const auto& f : param_fields<Params>()) m[f.keyword] = &f;
    return m;
  }();
  Params params;
  for (const auto& [key, value] : kwargs) {
    const std::string k = py::cast<std::string>(key);
    if (others.count(k)) continue;
    const auto it = by_keyword.find(k);
    if (it == by_keyword.end())
      throw py::type_error(function + "() got an unexpected keyword argument '" + k +
                           "' (help(detexture." + function + ") lists them all)");
    it->second->set(params, value);
  }
  return params;
}

/// A dict keyword -> default, from a default-constructed Params.
template <class Params>
py::dict default_params() {
  const Params defaults{};
  py::dict d;
  for (const auto& f : param_fields<Params>()) d[py::str(f.keyword)] = f.get(defaults);
  return d;
}

inline std::string wrap(const std::string& text, const std::string& indent,
                        std::size_t width = 76) {
  std::istringstream words(text);
  std::string out, line, word;
  while (words >> word) {
    if (!line.empty() && indent.size() + line.size() + 1 + word.size() > width) {
      out += indent + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += indent + line + "\n";
  return out;
}

/// ", kw=default" for every keyword (for a signature line), and the
/// "kw : type, default value" + doc list; enums name their values.
template <class Params>
std::pair<std::string, std::string> params_doc(const py::module_& m) {
  const Params defaults{};
  std::string signature, list;
  for (const auto& f : param_fields<Params>()) {
    const py::object v = f.get(defaults);
    const std::string value = (f.is_enum ? py::str(v) : py::repr(v)).template cast<std::string>();
    signature += ", " + f.keyword + "=" + value;
    std::string text = doc(f.doc_key);
    if (f.is_enum) {
      std::string names;
      for (const auto& item : py::dict(m.attr(f.type.c_str()).attr("__members__")))
        names += (names.empty() ? "" : ", ") + py::cast<std::string>(item.first);
      text += (text.empty() ? "" : " ") + std::string("One of ") + names + " (detexture." + f.type +
              " or its name as a string).";
    }
    list += f.keyword + " : " + f.type + ", default " + value + "\n" +
            wrap(text.empty() ? "(undocumented)" : text, "    ");
  }
  return {signature, list};
}

}  // namespace detexture::python
