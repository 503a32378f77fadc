// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The C++ instances of a system's host in one process (`processes: shared`): an
// rclcpp_components component container that loads its instances by itself and,
// with ACTIVATE, brings the managed ones up, as the shared Python process does
// (robmosys_runtime.hosting.container). It makes each node with its component's
// rclcpp_components factory, with the name, namespace, remappings and parameter
// file its own process would have, configures and activates each managed instance
// whose predecessors it activated itself, in the model's order, through the node's
// own transitions, then tells the system manager which it brought to which state:
// one line of JSON on a file descriptor (bringup reads a pipe) and/or in a file
// (the launch file's manager reads it), before it serves anything. The manager
// then neither loads each node through the container's load_node service nor
// discovers each node's lifecycle services to take it through two transitions:
// that was what it added to the floor of 50 C++ instances (1.64x, issue 28).
// Its load_node, unload_node and list_nodes services stay, as rclcpp_components'.
//
// robmosys_runtime.hosting.cpp_container reads the system's description and starts this
// program with everything on the command line, counted (no value is parsed):
//
//   component_container EXECUTOR THREADS ACTIVATE REPORT_FD REPORT_FILE COUNT
//       {INSTANCE PACKAGE PLUGIN MANAGED N_AFTER AFTER... N_ARGUMENTS ARGUMENT...}...
//       [--ros-args ...]
//
// EXECUTOR: events, single-threaded or multi-threaded (THREADS at least);
// ACTIVATE and MANAGED: 1 or 0; REPORT_FD: -1 for none; REPORT_FILE: empty for
// none; the ARGUMENTs are the node's ROS arguments (`--params-file FILE -r ...`).

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lifecycle_msgs/msg/state.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_components/component_manager.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"
#include "robmosys_runtime/main.hpp"

namespace
{

struct Instance
{
  std::string name;
  std::string package;
  std::string plugin;
  bool managed = false;
  std::vector<std::string> after;
  std::vector<std::string> arguments;
};

struct Options
{
  robmosys_runtime::Executor executor = robmosys_runtime::Executor::MULTI_THREADED;
  std::size_t threads = 1;
  bool activate = false;
  int report_fd = -1;
  std::string report_file;
  std::vector<Instance> instances;
  /// argv[0] and what follows --ros-args: the process's own arguments, for rclcpp::init
  std::vector<char *> ros_argv;
};

/// Read the words of argv in turn; a missing or malformed one throws.
class Words
{
public:
  Words(int argc, char ** argv)
  : argc_(argc), argv_(argv) {}

  std::string next()
  {
    if (at_ >= argc_) {
      throw std::invalid_argument("too few arguments");
    }
    return argv_[at_++];
  }

  std::size_t count()
  {
    const std::string word = next();
    std::size_t used = 0;
    const unsigned long value = std::stoul(word, &used);  // NOLINT(runtime/int)
    if (used != word.size()) {
      throw std::invalid_argument("not a count: " + word);
    }
    return value;
  }

  std::vector<std::string> list()
  {
    std::vector<std::string> words(count());
    for (auto & word : words) {
      word = next();
    }
    return words;
  }

  int at() const {return at_;}

private:
  int argc_;
  char ** argv_;
  int at_ = 1;
};

Options parse(int argc, char ** argv)
{
  static const std::map<std::string, robmosys_runtime::Executor> executors = {
    {"events", robmosys_runtime::Executor::EVENTS},
    {"single-threaded", robmosys_runtime::Executor::SINGLE_THREADED},
    {"multi-threaded", robmosys_runtime::Executor::MULTI_THREADED}};
  Words words(argc, argv);
  Options options;
  const std::string executor = words.next();
  if (executors.count(executor) == 0) {
    throw std::invalid_argument("no executor " + executor);
  }
  options.executor = executors.at(executor);
  options.threads = words.count();
  options.activate = words.next() == "1";
  options.report_fd = std::stoi(words.next());
  options.report_file = words.next();
  options.instances.resize(words.count());
  for (Instance & instance : options.instances) {
    instance.name = words.next();
    instance.package = words.next();
    instance.plugin = words.next();
    instance.managed = words.next() == "1";
    instance.after = words.list();
    instance.arguments = words.list();
    instance.arguments.insert(instance.arguments.begin(), "--ros-args");
  }
  options.ros_argv.push_back(argv[0]);
  for (int at = words.at(); at < argc; ++at) {
    options.ros_argv.push_back(argv[at]);
  }
  return options;
}

/// A string as JSON writes it (instance names are ROS names: this is for safety).
std::string json_string(const std::string & text)
{
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\u%04x", c);
      quoted += escaped;
    } else {
      quoted += c;
    }
  }
  return quoted + "\"";
}

/// Write all of a text to a file descriptor, then close it; false if it could not.
bool write_all(int fd, const std::string & text)
{
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t done = ::write(fd, text.data() + written, text.size() - written);
    if (done < 0) {
      return false;
    }
    written += static_cast<std::size_t>(done);
  }
  return true;
}

/// Write a file that its reader finds whole or not at all (a temporary file renamed).
bool write_whole(const std::string & path, const std::string & text)
{
  const std::string temporary = path + "." + std::to_string(::getpid()) + ".tmp";
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    stream << text;
    if (!stream.flush()) {
      return false;
    }
  }
  return std::rename(temporary.c_str(), path.c_str()) == 0;
}

/// rclcpp_components' container, which loads the instances it is given by itself.
class Container : public rclcpp_components::ComponentManager
{
public:
  using rclcpp_components::ComponentManager::ComponentManager;

  /// Make an instance's node with its component's factory and spin it, as load_node does.
  /**
   * \return the node: a generated component derives from rclcpp_lifecycle::LifecycleNode
   *   alone (robmosys_runtime::ComponentNode), so the instance's address is the base's
   * \throws rclcpp_components::ComponentManagerException if it cannot be made
   */
  std::shared_ptr<rclcpp_lifecycle::LifecycleNode> load(const Instance & instance)
  {
    auto & factory = factories_[instance.package + '\n' + instance.plugin];
    if (!factory) {
      for (const auto & resource : get_component_resources(instance.package)) {
        if (resource.first == instance.plugin) {
          factory = create_component_factory(resource);
          break;
        }
      }
    }
    if (!factory) {
      throw rclcpp_components::ComponentManagerException(
              "no component " + instance.plugin + " in the package " + instance.package);
    }
    const uint64_t id = unique_id_++;
    try {
      node_wrappers_[id] = factory->create_node_instance(
        rclcpp::NodeOptions().use_global_arguments(false).arguments(instance.arguments));
    } catch (const std::exception & error) {
      throw rclcpp_components::ComponentManagerException(
              "its component's constructor threw an exception: " + std::string(error.what()));
    }
    add_node_to_executor(id);
    return std::static_pointer_cast<rclcpp_lifecycle::LifecycleNode>(
      node_wrappers_[id].get_node_instance());
  }

  /// Forget every node (before the executor goes).
  void unload_all()
  {
    for (const auto & wrapper : node_wrappers_) {
      remove_node_from_executor(wrapper.first);
    }
    node_wrappers_.clear();
  }

private:
  std::map<std::string, std::shared_ptr<rclcpp_components::NodeFactory>> factories_;
};

/// Configure and activate the managed instances whose predecessors are active here.
/**
 * \return instance -> state, of those activated (active) and of those left as
 *   they were made (unconfigured: what they come after was not activated here);
 *   one that failed a transition is left out, for the manager to ask
 */
std::map<std::string, std::string> activate_in_order(
  const std::vector<Instance> & instances,
  const std::map<std::string, std::shared_ptr<rclcpp_lifecycle::LifecycleNode>> & nodes)
{
  using lifecycle_msgs::msg::State;
  std::map<std::string, std::string> states;
  std::set<std::string> active;
  for (const Instance & instance : instances) {
    const auto node = nodes.find(instance.name);
    if (!instance.managed || node == nodes.end()) {
      continue;
    }
    bool ready = true;
    for (const std::string & predecessor : instance.after) {
      ready = ready && active.count(predecessor) > 0;
    }
    if (!ready) {
      states[instance.name] = "unconfigured";
      continue;
    }
    const auto & lifecycle = node->second;
    if (lifecycle->configure().id() == State::PRIMARY_STATE_INACTIVE &&
      lifecycle->activate().id() == State::PRIMARY_STATE_ACTIVE)
    {
      states[instance.name] = "active";
      active.insert(instance.name);
    }
  }
  return states;
}

/// Tell the manager the states known: a line of JSON, on the descriptor and in the file.
/**
 * The descriptor stays open: bringup reads on it the steps of the bring-down
 * (bring_down()), where this process holds every managed instance.
 */
void tell(Options & options, const std::map<std::string, std::string> & states)
{
  std::string line = "{";
  for (const auto & state : states) {
    line += (line.size() > 1 ? ", " : "") + json_string(state.first) + ": " +
      json_string(state.second);
  }
  line += "}\n";
  // a reader that stopped reading, or a file that cannot be written: the manager
  // asks the instances instead
  if (options.report_fd >= 0 && !write_all(options.report_fd, line)) {
    std::fprintf(stderr, "component_container: could not tell the manager on %d\n",
      options.report_fd);
    ::close(options.report_fd);
    options.report_fd = -1;
  }
  if (!options.report_file.empty() && !write_whole(options.report_file, line)) {
    std::fprintf(stderr, "component_container: error: %s: could not be written\n",
      options.report_file.c_str());
  }
}

/// A node the container made, as Ctrl-C finds it.
struct Held
{
  std::string name;
  bool managed;
  std::weak_ptr<rclcpp_lifecycle::LifecycleNode> node;
};

/// Where a bring-down tells its steps: set once the bring-up is told.
struct Steps
{
  static constexpr int not_up = -2;
  std::mutex mutex;
  int fd = not_up;
};

/// Deactivate, then clean up, the managed instances here, the last activated first.
/**
 * What bringup does through the lifecycle services, done in this process (as
 * robmosys_runtime.hosting.container does for the Python instances), each step told on
 * fd (``deactivate <instance>``, ``cleanup <instance>``, ``error: ...``), which
 * is then closed. An instance found unconfigured is left so.
 */
void bring_down(const std::vector<Held> & held, int fd)
{
  using lifecycle_msgs::msg::State;
  for (auto it = held.rbegin(); it != held.rend(); ++it) {
    auto node = it->node.lock();
    if (!it->managed || !node) {
      continue;
    }
    for (const auto & step : {std::make_pair(State::PRIMARY_STATE_ACTIVE, "deactivate"),
        std::make_pair(State::PRIMARY_STATE_INACTIVE, "cleanup")})
    {
      if (node->get_current_state().id() != step.first) {
        continue;
      }
      const std::string verb = step.second;
      const auto reached = verb == "deactivate" ? node->deactivate() : node->cleanup();
      const bool done = reached.id() == (verb == "deactivate" ?
        State::PRIMARY_STATE_INACTIVE : State::PRIMARY_STATE_UNCONFIGURED);
      const std::string line = done ? verb + " " + it->name + "\n" :
        "error: instance " + it->name + " could not be brought down: failed to " + verb +
        " (it is " + reached.label() + ")\n";
      // bringup stopped reading: it asks the instances
      if (fd >= 0 && !write_all(fd, line)) {
        ::close(fd);
        fd = -1;
      }
      if (!done) {
        break;
      }
    }
  }
  if (fd >= 0) {
    ::close(fd);
  }
}

}  // namespace

int main(int argc, char ** argv)
{
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const std::exception & error) {
    std::fprintf(stderr, "component_container: error: %s (it is started by "
      "robmosys_runtime.hosting.cpp_container)\n", error.what());
    return 2;
  }
  // a pipe bringup no longer reads fails a write, and does not end the process
  std::signal(SIGPIPE, SIG_IGN);
  rclcpp::init(static_cast<int>(options.ros_argv.size()), options.ros_argv.data());
  int status = 0;
  {
    auto executor = robmosys_runtime::make_executor(options.executor, options.threads);
    auto container = std::make_shared<Container>(executor);
    std::map<std::string, std::shared_ptr<rclcpp_lifecycle::LifecycleNode>> nodes;
    for (const Instance & instance : options.instances) {
      try {
        nodes[instance.name] = container->load(instance);
      } catch (const std::exception & error) {
        // the manager finds it missing, and reports it
        RCLCPP_ERROR(
          container->get_logger(), "instance %s could not be loaded: %s",
          instance.name.c_str(), error.what());
      }
    }
    // Ctrl-C: once it brought them up, the managed instances are brought down
    // (deactivate, cleanup), as the Python process does; then each node takes
    // its shutdown transition (its on_shutdown functions run, its ports are
    // released), while it can still tell its lifecycle clients
    std::vector<Held> held;
    for (const Instance & instance : options.instances) {
      if (nodes.count(instance.name) > 0) {
        held.push_back({instance.name, instance.managed, nodes[instance.name]});
      }
    }
    // where the steps go once the bring-up is told (-1: nowhere); until then
    // a Ctrl-C only shuts the nodes down, and a bring-down is done once. The
    // Ctrl-C is taken in rclcpp's signal thread: one that comes while the
    // bring-up is told waits until it is, and then brings the instances down
    // (it was taken for "not up" between the two, and told no step)
    auto steps = std::make_shared<Steps>();
    rclcpp::contexts::get_global_default_context()->add_pre_shutdown_callback(
      [held, steps]() {
        int fd;
        {
          std::lock_guard<std::mutex> lock(steps->mutex);
          fd = std::exchange(steps->fd, Steps::not_up);
        }
        if (fd != Steps::not_up) {
          bring_down(held, fd);
        }
        const auto finalized = lifecycle_msgs::msg::State::PRIMARY_STATE_FINALIZED;
        for (auto it = held.rbegin(); it != held.rend(); ++it) {
          auto alive = it->node.lock();
          if (alive && alive->get_current_state().id() != finalized) {
            alive->shutdown();
          }
        }
      });
    if (options.activate) {
      const auto states = activate_in_order(options.instances, nodes);
      std::lock_guard<std::mutex> lock(steps->mutex);
      tell(options, states);
      steps->fd = options.report_fd;
    }
    nodes.clear();
    executor->add_node(container);
    try {
      executor->spin();
    } catch (const std::exception & error) {
      RCLCPP_FATAL(container->get_logger(), "%s", error.what());
      status = 1;
    }
    executor->remove_node(container);
    container->unload_all();
  }
  rclcpp::shutdown();
  return status;
}
