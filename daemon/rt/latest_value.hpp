#pragma once
// Triple buffer: one writer publishes the latest value every cycle, readers on other
// threads take the newest complete one. Wait-free for the writer, no torn reads, and every
// buffer is owned by exactly one side at a time (clean under ThreadSanitizer, unlike a
// seqlock). Readers are serialised by a mutex on the non-RT side only.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <type_traits>

namespace rig::rt {

template <typename T>
class LatestValue {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  void publish(const T& value) noexcept {  // RT side
    buffers_[back_] = value;
    const std::uint8_t previous =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
  }

  T read() {  // non-RT side
    std::lock_guard lock(reader_mutex_);
    if ((middle_.load(std::memory_order_acquire) & kFresh) != 0) {
      const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
      front_ = previous & kIndexMask;
    }
    return buffers_[front_];
  }

 private:
  static constexpr std::uint8_t kFresh = 0x4;
  static constexpr std::uint8_t kIndexMask = 0x3;
  T buffers_[3]{};
  std::uint8_t back_ = 0;                // writer's buffer
  std::atomic<std::uint8_t> middle_{1};  // last published buffer (+ fresh flag)
  std::uint8_t front_ = 2;               // reader's buffer
  std::mutex reader_mutex_;
};

}  // namespace rig::rt
