// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The rules of a component's parameters beyond their descriptors, and what runs on a change.

#ifndef ROBMOSYS_RUNTIME__PARAMETERS_HPP_
#define ROBMOSYS_RUNTIME__PARAMETERS_HPP_

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"

namespace robmosys_runtime
{

namespace detail
{

/// The element type of an array parameter, the type itself of another.
template<typename T>
struct element
{
  using type = T;
};

template<typename T>
struct element<std::vector<T>>
{
  using type = T;
};

/// Write a value as robmosys_runtime's Python module and colcon-robmosys's checks do.
inline void write(std::ostringstream & out, const std::string & value)
{
  out << '\'' << value << '\'';
}

inline void write(std::ostringstream & out, bool value)
{
  out << (value ? "True" : "False");
}

inline void write(std::ostringstream & out, uint8_t value)
{
  out << static_cast<int>(value);
}

template<typename T>
void write(std::ostringstream & out, const T & value)
{
  out << value;
}

template<typename T>
void write(std::ostringstream & out, const std::vector<T> & values)
{
  out << '[';
  for (std::size_t i = 0; i < values.size(); ++i) {
    out << (i ? ", " : "");
    write(out, static_cast<T>(values[i]));
  }
  out << ']';
}

template<typename T>
std::string listed(const std::vector<T> & values)
{
  std::ostringstream out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    out << (i ? ", " : "");
    write(out, static_cast<T>(values[i]));
  }
  return out.str();
}

template<typename T>
std::string shown(const T & value)
{
  std::ostringstream out;
  write(out, value);
  return out.str();
}

/// The characters of a UTF-8 string (code points, as Python counts them).
inline std::size_t length(const std::string & value)
{
  std::size_t count = 0;
  for (const char c : value) {
    count += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  }
  return count;
}

template<typename T>
std::size_t length(const std::vector<T> & values)
{
  return values.size();
}

template<typename T>
std::size_t length(const T &)
{
  return 0;
}

template<typename T>
std::string one_of_problem(const T & value, const std::vector<T> & allowed)
{
  for (const auto & candidate : allowed) {
    if (candidate == value) {
      return "";
    }
  }
  return shown(value) + " is not one of " + listed(allowed);
}

template<typename T>
std::string one_of_problem(const std::vector<T> & values, const std::vector<T> & allowed)
{
  for (std::size_t i = 0; i < values.size(); ++i) {
    const T value = values[i];
    if (!one_of_problem(value, allowed).empty()) {
      return "element " + shown(value) + " is not one of " + listed(allowed);
    }
  }
  return "";
}

}  // namespace detail

/// What a value of one parameter of type T must be, and what runs after it changes.
template<typename T>
struct ParameterRule
{
  using Element = typename detail::element<T>::type;

  /// The values it may take; of an array, those its elements may take.
  std::optional<std::vector<Element>> one_of;
  /// Characters of a string or elements of an array, inclusive; no max: no bound.
  std::optional<std::size_t> min_size;
  std::optional<std::size_t> max_size;
  /// A function of the component: why a value is refused, or an empty string.
  std::function<std::string(const T &)> validate;
  /// Functions of the component run after an accepted change, in order.
  std::vector<std::function<void()>> on_change;
};

/// The rules of a node's parameters, checked in its on-set-parameters callback.
/**
 * Create it before the parameters are declared, so that a value given at
 * start breaks no rule either, and call start() once they are (at the end of
 * the generated constructor): the component's validators and on_change
 * functions are virtual functions, which run from then on only; on configure,
 * check_current() runs the validators over the values of the moment. The
 * words of the reasons are those of robmosys_runtime's Python module.
 */
class ParameterRules
{
public:
  explicit ParameterRules(rclcpp_lifecycle::LifecycleNode & node)
  : node_(node)
  {
    on_set_ = node_.add_on_set_parameters_callback(
      [this](const std::vector<rclcpp::Parameter> & parameters) {
        rcl_interfaces::msg::SetParametersResult result;
        result.successful = true;
        for (const auto & parameter : parameters) {
          const std::string problem = this->problem(parameter);
          if (!problem.empty()) {
            result.successful = false;
            result.reason = problem;
            break;
          }
        }
        return result;
      });
  }

  /// Add the rule of a parameter of type T.
  template<typename T>
  void add(const std::string & name, ParameterRule<T> rule)
  {
    Entry entry;
    entry.check = [name, rule](const rclcpp::Parameter & parameter, bool validate) {
        std::string problem;
        if (parameter.get_type() != rclcpp::ParameterValue(T{}).get_type()) {
          return problem;  // the descriptor refuses another type
        }
        const T value = parameter.get_value<T>();
        if (rule.one_of) {
          problem = detail::one_of_problem(value, *rule.one_of);
        }
        const std::size_t size = detail::length(value);
        const char * unit = std::is_same<T, std::string>::value ? " characters" : " elements";
        if (problem.empty() && rule.min_size && size < *rule.min_size) {
          problem = detail::shown(value) + " has " + std::to_string(size) + unit +
            ", fewer than " + std::to_string(*rule.min_size);
        }
        if (problem.empty() && rule.max_size && size > *rule.max_size) {
          problem = detail::shown(value) + " has " + std::to_string(size) + unit +
            ", more than " + std::to_string(*rule.max_size);
        }
        if (problem.empty() && validate && rule.validate) {
          problem = rule.validate(value);
        }
        return problem.empty() ? problem : "parameter '" + name + "': " + problem;
      };
    entry.on_change = rule.on_change;
    entries_[name] = std::move(entry);
  }

  /// Run the validators on every change from now on, and the on_change functions.
  void start()
  {
    started_ = true;
    post_set_ = node_.add_post_set_parameters_callback(
      [this](const std::vector<rclcpp::Parameter> & parameters) {
        for (const auto & parameter : parameters) {
          auto found = entries_.find(parameter.get_name());
          if (found == entries_.end()) {
            continue;
          }
          for (const auto & function : found->second.on_change) {
            try {
              function();
            } catch (const std::exception & error) {
              RCLCPP_ERROR(
                node_.get_logger(), "on_change of %s failed: %s",
                parameter.get_name().c_str(), error.what());
            }
          }
        }
      });
  }

  /// Throw std::runtime_error if a current value is refused (on configure).
  void check_current() const
  {
    for (const auto & entry : entries_) {
      const std::string problem = entry.second.check(node_.get_parameter(entry.first), true);
      if (!problem.empty()) {
        throw std::runtime_error(problem);
      }
    }
  }

  /// Return why a parameter may not take a value, or an empty string.
  std::string problem(const rclcpp::Parameter & parameter) const
  {
    auto found = entries_.find(parameter.get_name());
    if (found == entries_.end()) {
      return "";
    }
    try {
      return found->second.check(parameter, started_);
    } catch (const std::exception & error) {
      return "parameter '" + parameter.get_name() + "': its validator failed: " + error.what();
    }
  }

private:
  struct Entry
  {
    std::function<std::string(const rclcpp::Parameter &, bool)> check;
    std::vector<std::function<void()>> on_change;
  };

  rclcpp_lifecycle::LifecycleNode & node_;
  std::map<std::string, Entry> entries_;
  bool started_ = false;
  rclcpp::node_interfaces::OnSetParametersCallbackHandle::SharedPtr on_set_;
  rclcpp::node_interfaces::PostSetParametersCallbackHandle::SharedPtr post_set_;
};

/// Return the name of a mapped parameter for an entry: its pattern, the entry for its {}.
inline std::string mapped_name(const std::string & pattern, const std::string & entry)
{
  std::string name = pattern;
  const std::size_t at = name.find("{}");
  if (at != std::string::npos) {
    name.replace(at, 2, entry);
  }
  return name;
}

/// Tell whether an entry is one part of a parameter name (as colcon-robmosys's checks).
inline bool is_name_part(const std::string & entry)
{
  const auto first = entry.empty() ? 0 : static_cast<unsigned char>(entry[0]);
  if (first >= 128 || !std::isalpha(first) ||
    entry.find("__") != std::string::npos)
  {
    return false;
  }
  return std::all_of(
    entry.begin(), entry.end(), [](char c) {
      const auto byte = static_cast<unsigned char>(c);
      return c == '_' || (byte < 128 && std::isalnum(byte));
    });
}

/// Return the entries of an array parameter that mapped parameters are repeated for.
/**
 * Each entry is one part of a parameter name, listed once, and none of the
 * names it gives (patterns, {} for the entry) is a parameter the node has
 * already; std::invalid_argument says which is not, in the words of
 * robmosys_runtime's Python module.
 */
inline std::vector<std::string> map_entries(
  rclcpp_lifecycle::LifecycleNode & node, const std::string & array,
  const std::vector<std::string> & patterns)
{
  const std::vector<std::string> entries = node.get_parameter(array).as_string_array();
  std::vector<std::string> seen;
  for (const auto & entry : entries) {
    std::string problem;
    if (!is_name_part(entry)) {
      problem = "entry " + detail::shown(entry) + " is not a parameter name part (a letter, " +
        "then letters, digits and single underscores)";
    } else if (std::find(seen.begin(), seen.end(), entry) != seen.end()) {
      problem = "entry " + detail::shown(entry) + " is listed twice";
    } else {
      for (const auto & pattern : patterns) {
        const std::string name = mapped_name(pattern, entry);
        if (node.has_parameter(name)) {
          problem = "entry " + detail::shown(entry) + " gives the parameter '" + name +
            "', which the component has";
          break;
        }
      }
    }
    if (!problem.empty()) {
      throw std::invalid_argument("parameter '" + array + "': " + problem);
    }
    seen.push_back(entry);
  }
  return entries;
}

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__PARAMETERS_HPP_
