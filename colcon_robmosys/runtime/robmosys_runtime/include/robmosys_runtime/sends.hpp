// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#ifndef ROBMOSYS_RUNTIME__SENDS_HPP_
#define ROBMOSYS_RUNTIME__SENDS_HPP_

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

#include "rclcpp_lifecycle/lifecycle_publisher.hpp"

namespace robmosys_runtime
{

/// Return the key of a topic's send files: FNV-1a (64 bits) of its name, in hex.
inline std::string topic_key(const std::string & topic)
{
  std::uint64_t value = 0xcbf29ce484222325ULL;
  for (const char c : topic) {
    value = (value ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(value));  // NOLINT
  return text;
}

/// The time of a publisher's last send, kept where the bringup that started the process asks.
/**
 * As robmosys_runtime/sends.py does for Python components: where the
 * environment names a directory in ROBMOSYS_SENDS, a file of eight bytes,
 * <key>-<pid>-c<n>, holds the CLOCK_MONOTONIC time in nanoseconds of the last
 * send; the bringup reads it once per check period, and needs no copy of the
 * messages. Without the variable, stamp() does nothing.
 */
class SendStamp
{
public:
  explicit SendStamp(const std::string & topic)
  {
    const char * directory = std::getenv("ROBMOSYS_SENDS");
    if (directory == nullptr || *directory == '\0') {
      return;
    }
    static std::atomic<unsigned> numbers{0};
    const std::string path = std::string(directory) + "/" + topic_key(topic) + "-" +
      std::to_string(::getpid()) + "-c" + std::to_string(numbers++);
    const int descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (descriptor < 0) {
      return;  // the bringup that asked has gone: the watch ends with it
    }
    if (::ftruncate(descriptor, sizeof(std::int64_t)) == 0) {
      void * mapped = ::mmap(
        nullptr, sizeof(std::int64_t), PROT_READ | PROT_WRITE, MAP_SHARED, descriptor, 0);
      if (mapped != MAP_FAILED) {
        slot_ = static_cast<std::int64_t *>(mapped);
      }
    }
    ::close(descriptor);
  }

  SendStamp(const SendStamp &) = delete;
  SendStamp & operator=(const SendStamp &) = delete;

  ~SendStamp()
  {
    if (slot_ != nullptr) {
      ::munmap(slot_, sizeof(std::int64_t));
    }
  }

  /// Keep now as the time of the last send.
  void stamp() noexcept
  {
    if (slot_ != nullptr) {
      const auto now = std::chrono::steady_clock::now().time_since_epoch();
      __atomic_store_n(
        slot_, std::chrono::duration_cast<std::chrono::nanoseconds>(now).count(),
        __ATOMIC_RELAXED);
    }
  }

private:
  std::int64_t * slot_ = nullptr;
};

/// A lifecycle publisher that keeps the time of its last send (the port of a component).
template<typename MessageT, typename Alloc = std::allocator<void>>
class CountedPublisher : public rclcpp_lifecycle::LifecyclePublisher<MessageT, Alloc>
{
public:
  using Base = rclcpp_lifecycle::LifecyclePublisher<MessageT, Alloc>;
  using SharedPtr = std::shared_ptr<CountedPublisher>;
  using Base::Base;

  /// Publish as a lifecycle publisher does: only a send while activated counts.
  template<typename ... Args>
  void publish(Args && ... args)
  {
    Base::publish(std::forward<Args>(args)...);
    if (this->is_activated()) {
      stamp_.stamp();
    }
  }

private:
  SendStamp stamp_{this->get_topic_name()};
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__SENDS_HPP_
