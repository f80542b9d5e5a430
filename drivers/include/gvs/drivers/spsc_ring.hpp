// Bounded single-producer single-consumer ring of preallocated slots.
//
// The capture thread (producer) claims a free slot, fills it in place and
// publishes it; the processing thread (consumer) takes the newest published
// slot, releasing every older one unread (it always works on the newest
// frame), and releases the slot it holds when done. No locks, no allocation
// after construction; head and tail are monotonically increasing counters
// on their own cache lines.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gvs::drivers {

template <typename Slot>
class SpscRing {
 public:
  /// Takes the preallocated slots (at least 2).
  explicit SpscRing(std::vector<Slot> slots) : slots_(std::move(slots)) {
    if (slots_.size() < 2) throw std::invalid_argument("SpscRing: needs at least 2 slots");
  }
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  [[nodiscard]] std::size_t capacity() const noexcept { return slots_.size(); }

  // ---- producer side (one thread) ----

  /// The slot to fill next, or nullptr when every slot is published or held
  /// by the consumer (the ring is full).
  [[nodiscard]] Slot* try_claim() noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    if (head - tail >= slots_.size()) return nullptr;
    return &slots_[static_cast<std::size_t>(head % slots_.size())];
  }
  /// Makes the slot returned by the last try_claim() visible to the consumer.
  void publish() noexcept {
    head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  // ---- consumer side (one thread) ----

  /// The newest published slot, or nullptr when none is waiting. Older
  /// published slots are given back to the producer unread; their number is
  /// stored in `skipped`. Call release() when done with the slot.
  [[nodiscard]] Slot* take_newest(std::uint64_t& skipped) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    skipped = 0;
    if (head == tail) return nullptr;
    skipped = head - tail - 1;
    if (skipped != 0) tail_.store(head - 1, std::memory_order_release);
    return &slots_[static_cast<std::size_t>((head - 1) % slots_.size())];
  }
  /// The oldest published slot (FIFO use), or nullptr when none is waiting.
  /// Call release() when done with it.
  [[nodiscard]] Slot* take_oldest() noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    if (head == tail) return nullptr;
    return &slots_[static_cast<std::size_t>(tail % slots_.size())];
  }
  /// Gives the slot from take_newest() / take_oldest() back to the producer.
  void release() noexcept {
    tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  /// Slots published and not yet taken (approximate from other threads).
  [[nodiscard]] std::uint64_t size_approx() const noexcept {
    return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
  }

  /// Direct access for start-up preparation (before the threads run).
  [[nodiscard]] std::vector<Slot>& slots_for_setup() noexcept { return slots_; }

 private:
  static constexpr std::size_t kLine = 64;
  std::vector<Slot> slots_;
  alignas(kLine) std::atomic<std::uint64_t> head_{0};  // written by the producer
  alignas(kLine) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
};

}  // namespace gvs::drivers
