// A std::vector whose growth without a value leaves new elements of a trivial type as the memory
// held them: `NoFillVector<float> v(n)` and `v.resize(n)` write nothing, where std::vector writes
// n zeros first. For the image planes every pixel of which the next loop writes anyway: at 1080p
// each zero fill is another pass over 8 to 33 MB. Growth with a value (`v(n, x)`, `resize(n, x)`)
// and everything else are std::vector's. Read nothing you have not written.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace glintlab {

template <typename T, typename Base = std::allocator<T>>
struct NoFillAllocator : Base {
  using Base::Base;
  NoFillAllocator() = default;
  template <typename U>
  struct rebind {
    using other = NoFillAllocator<U, typename std::allocator_traits<Base>::template rebind_alloc<U>>;
  };
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;  // default-initialised: nothing written for a trivial U
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    std::allocator_traits<Base>::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
  }
};

template <typename T>
using NoFillVector = std::vector<T, NoFillAllocator<T>>;

}  // namespace glintlab
