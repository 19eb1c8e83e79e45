// buffer.hpp - Buffer<T>: the solver's large per-point arrays, allocated without being written.
//
// A std::vector whose resize() leaves new elements default-initialised: for the arithmetic
// types and plain structs it holds, not written at all. The loop that fills a buffer then
// touches its pages for the first time, on every thread of the parallel, where std::vector would
// have zeroed them all on the calling thread first. A first touch is a page fault, which costs
// 8-15 us per 4 KiB page on the virtual machines we measure on: zeroing the association, cache
// and weight buffers of a 65k-point registration took 26-34 ms on one thread
// (docs/PERFORMANCE.md).
//
// Only for buffers whose every element is written before it is read.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// std::allocator, but constructing without arguments by default-initialisation.
template <class T>
class BufferAllocator : public std::allocator<T> {
 public:
  template <class U>
  struct rebind {
    using other = BufferAllocator<U>;
  };
  BufferAllocator() noexcept = default;
  template <class U>
  BufferAllocator(const BufferAllocator<U>&) noexcept {}  // NOLINT: allocators convert implicitly

  /// Default-initialisation: no write for trivially constructible types.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using Buffer = std::vector<T, BufferAllocator<T>>;

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
