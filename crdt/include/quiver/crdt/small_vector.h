#pragma once
/// @file
/// A vector with inline room for N elements: registers and dot sets almost always hold one
/// entry, so they should not pay a heap allocation and a pointer chase for it.
///
/// Unlike std::vector: the capacity is a 32-bit count, indices are not checked, and moving a
/// SmallVec invalidates pointers to its inline elements (growing it invalidates all pointers).
/// Threading: no synchronization (as std::vector).

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
  /// Copies the elements of `init`.
  SmallVec(std::initializer_list<T> init) {
    reserve(init.size());
    for (const T& v : init) push_back(v);
  }
  /// Copies `o`'s elements.
  SmallVec(const SmallVec& o) {
    reserve(o.size_);
    for (const T& v : o) push_back(v);
  }
  /// Takes `o`'s elements (moving inline ones); `o` is left empty.
  /// @pre T's move constructor does not throw.
  SmallVec(SmallVec&& o) noexcept { take(std::move(o)); }
  /// Replaces the elements with copies of `o`'s.
  SmallVec& operator=(const SmallVec& o) {
    if (this != &o) {
      clear();
      reserve(o.size_);
      for (const T& v : o) push_back(v);
    }
    return *this;
  }
  /// Replaces the elements with `o`'s; `o` is left empty. @pre as the move constructor.
  SmallVec& operator=(SmallVec&& o) noexcept {
    if (this != &o) {
      destroy_all();
      take(std::move(o));
    }
    return *this;
  }
  /// Destroys the elements and frees any heap storage.
  ~SmallVec() { destroy_all(); }

  /// @returns the number of elements.
  std::size_t size() const { return size_; }
  /// @returns true if there is no element.
  bool empty() const { return size_ == 0; }
  /// @returns the contiguous storage (inline or heap).
  T* data() { return ptr(); }
  /// @returns the contiguous storage (inline or heap).
  const T* data() const { return ptr(); }
  /// @returns a pointer to the first element.
  T* begin() { return ptr(); }
  /// @returns a pointer one past the last element.
  T* end() { return ptr() + size_; }
  /// @returns a pointer to the first element.
  const T* begin() const { return ptr(); }
  /// @returns a pointer one past the last element.
  const T* end() const { return ptr() + size_; }
  /// @returns element `i`. @pre i < size() (unchecked).
  T& operator[](std::size_t i) { return ptr()[i]; }
  /// @returns element `i`. @pre i < size() (unchecked).
  const T& operator[](std::size_t i) const { return ptr()[i]; }
  /// @returns the first element. @pre !empty().
  T& front() { return ptr()[0]; }
  /// @returns the first element. @pre !empty().
  const T& front() const { return ptr()[0]; }
  /// @returns the last element. @pre !empty().
  T& back() { return ptr()[size_ - 1]; }
  /// @returns the last element. @pre !empty().
  const T& back() const { return ptr()[size_ - 1]; }

  /// Makes room for `n` elements in all (moving them to the heap if it grows).
  /// @pre n <= UINT32_MAX.
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
  /// Constructs an element at the end, doubling the capacity when full.
  /// @pre `args` do not refer into this vector (growth moves the elements first).
  /// @returns the new element.
  template <class... Args>
  T& emplace_back(Args&&... args) {
    if (size_ == cap_) reserve(cap_ * 2);
    T* slot = ptr() + size_;
    ::new (slot) T(std::forward<Args>(args)...);
    ++size_;
    return *slot;
  }
  /// Appends a copy of `v`. @pre `v` is not an element of this vector.
  void push_back(const T& v) { emplace_back(v); }
  /// Appends `v`, moved. @pre `v` is not an element of this vector.
  void push_back(T&& v) { emplace_back(std::move(v)); }
  /// Destroys the last element. @pre !empty().
  void pop_back() {
    --size_;
    ptr()[size_].~T();
  }
  /// Removes the element at `it` by moving the last one into its place (order not kept).
  /// @pre begin() <= it < end().
  /// @returns `it`, which now holds the former last element (or equals end()).
  T* swap_erase(T* it) {
    T* last = end() - 1;
    if (it != last) *it = std::move(*last);
    pop_back();
    return it;
  }
  /// Removes the element at `it`, keeping order.
  /// @pre begin() <= it < end().
  /// @returns `it`, now the element that followed the removed one (or end()).
  T* erase(T* it) {
    std::move(it + 1, end(), it);
    pop_back();
    return it;
  }
  /// Removes the elements for which pred(element) is true, keeping the others' order.
  /// @returns how many were removed.
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
  /// Destroys every element; the capacity is kept.
  void clear() {
    for (std::size_t i = 0; i < size_; ++i) ptr()[i].~T();
    size_ = 0;
  }

  /// @returns true if both hold equal elements in the same order.
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
