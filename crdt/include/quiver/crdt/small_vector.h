#pragma once
/// @file
/// A vector with inline room for N elements: registers and dot sets almost always hold one
/// entry, so they should not pay a heap allocation and a pointer chase for it.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <new>
#include <utility>

namespace quiver::crdt {

template <class T, std::size_t N>
class SmallVec {
  static_assert(N >= 1);

 public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  SmallVec() = default;
  SmallVec(std::initializer_list<T> init) {
    reserve(init.size());
    for (const T& v : init) push_back(v);
  }
  SmallVec(const SmallVec& o) {
    reserve(o.size_);
    for (const T& v : o) push_back(v);
  }
  SmallVec(SmallVec&& o) noexcept { take(std::move(o)); }
  SmallVec& operator=(const SmallVec& o) {
    if (this != &o) {
      clear();
      reserve(o.size_);
      for (const T& v : o) push_back(v);
    }
    return *this;
  }
  SmallVec& operator=(SmallVec&& o) noexcept {
    if (this != &o) {
      destroy_all();
      take(std::move(o));
    }
    return *this;
  }
  ~SmallVec() { destroy_all(); }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return ptr(); }
  const T* data() const { return ptr(); }
  T* begin() { return ptr(); }
  T* end() { return ptr() + size_; }
  const T* begin() const { return ptr(); }
  const T* end() const { return ptr() + size_; }
  T& operator[](std::size_t i) { return ptr()[i]; }
  const T& operator[](std::size_t i) const { return ptr()[i]; }
  T& front() { return ptr()[0]; }
  const T& front() const { return ptr()[0]; }
  T& back() { return ptr()[size_ - 1]; }
  const T& back() const { return ptr()[size_ - 1]; }

  void reserve(std::size_t n) {
    if (n <= cap_) return;
    T* fresh = static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(alignof(T))));
    T* old = ptr();
    for (std::size_t i = 0; i < size_; ++i) {
      ::new (fresh + i) T(std::move(old[i]));
      old[i].~T();
    }
    release_heap();
    heap_ = fresh;
    cap_ = static_cast<std::uint32_t>(n);
  }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    if (size_ == cap_) reserve(cap_ * 2);
    T* slot = ptr() + size_;
    ::new (slot) T(std::forward<Args>(args)...);
    ++size_;
    return *slot;
  }
  void push_back(const T& v) { emplace_back(v); }
  void push_back(T&& v) { emplace_back(std::move(v)); }
  void pop_back() {
    --size_;
    ptr()[size_].~T();
  }
  /// Removes the element at `it` by moving the last one into its place (order not kept).
  T* swap_erase(T* it) {
    T* last = end() - 1;
    if (it != last) *it = std::move(*last);
    pop_back();
    return it;
  }
  /// Removes the element at `it`, keeping order.
  T* erase(T* it) {
    std::move(it + 1, end(), it);
    pop_back();
    return it;
  }
  template <class Pred>
  std::size_t erase_if(Pred pred) {
    T* out = begin();
    for (T* in = begin(); in != end(); ++in) {
      if (!pred(*in)) {
        if (out != in) *out = std::move(*in);
        ++out;
      }
    }
    std::size_t removed = static_cast<std::size_t>(end() - out);
    while (end() != out) pop_back();
    return removed;
  }
  void clear() {
    for (std::size_t i = 0; i < size_; ++i) ptr()[i].~T();
    size_ = 0;
  }

  friend bool operator==(const SmallVec& a, const SmallVec& b) {
    return a.size_ == b.size_ && std::equal(a.begin(), a.end(), b.begin());
  }

 private:
  T* inline_ptr() { return std::launder(reinterpret_cast<T*>(inline_)); }
  const T* inline_ptr() const { return std::launder(reinterpret_cast<const T*>(inline_)); }
  T* ptr() { return heap_ ? heap_ : inline_ptr(); }
  const T* ptr() const { return heap_ ? heap_ : inline_ptr(); }
  void release_heap() {
    if (heap_) ::operator delete(heap_, std::align_val_t(alignof(T)));
    heap_ = nullptr;
  }
  void destroy_all() {
    clear();
    release_heap();
    cap_ = N;
  }
  void take(SmallVec&& o) {
    if (o.heap_) {
      heap_ = o.heap_;
      cap_ = o.cap_;
      size_ = o.size_;
      o.heap_ = nullptr;
      o.cap_ = N;
      o.size_ = 0;
      return;
    }
    for (std::size_t i = 0; i < o.size_; ++i) ::new (inline_ptr() + i) T(std::move(o.inline_ptr()[i]));
    size_ = o.size_;
    o.clear();
  }

  T* heap_ = nullptr;
  std::uint32_t size_ = 0;
  std::uint32_t cap_ = N;
  alignas(T) unsigned char inline_[N * sizeof(T)];
};

}  // namespace quiver::crdt
