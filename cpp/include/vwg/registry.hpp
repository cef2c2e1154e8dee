// Factories by name, so a world file, a command line or an embedding app can say "astar", "sim",
// "laser" or "trace" and a third party can add its own without editing vwg. One registry per kind
// of part (deciders, platforms, sensors, backends); the Python package's registries (vwg.registry)
// take the built-in names from these.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "vwg/error.hpp"

namespace vwg {

template <class Product, class... Args>
class Registry {
 public:
  using Factory = std::function<std::shared_ptr<Product>(Args...)>;

  /// `kind` names the parts in errors ("unknown decider 'x' (known: astar, dstar)").
  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

  /// Throws SchemaError for an empty name, a name already taken, or no factory.
  void add(const std::string& name, Factory factory) {
    if (name.empty()) throw SchemaError(kind_, "a name is needed to register a " + kind_);
    if (!factory) throw SchemaError(kind_ + " '" + name + "'", "no factory given");
    std::lock_guard lock(mutex_);
    if (!factories_.emplace(name, std::move(factory)).second) {
      throw SchemaError(kind_ + " '" + name + "'", "is already registered");
    }
  }
  bool contains(const std::string& name) const {
    std::lock_guard lock(mutex_);
    return factories_.contains(name);
  }
  /// The registered names, sorted.
  std::vector<std::string> names() const {
    std::lock_guard lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [name, _] : factories_) out.push_back(name);
    return out;
  }
  /// A new part; throws SchemaError naming the known ones for an unknown name.
  std::shared_ptr<Product> create(const std::string& name, Args... args) const {
    Factory factory;
    {
      std::lock_guard lock(mutex_);
      auto it = factories_.find(name);
      if (it == factories_.end()) {
        std::string known;
        for (const auto& [n, _] : factories_) known += (known.empty() ? "" : ", ") + n;
        throw SchemaError(kind_, "unknown " + kind_ + " '" + name + "' (known: " + (known.empty() ? "none" : known) + ")");
      }
      factory = it->second;
    }
    return factory(std::forward<Args>(args)...);
  }
  const std::string& kind() const { return kind_; }

 private:
  std::string kind_;
  mutable std::mutex mutex_;
  std::map<std::string, Factory> factories_;
};

class Backend;
/// Backends by name: "trace" (TraceBackend) and "null" (NullBackend) built in.
Registry<Backend>& backends();

}  // namespace vwg
