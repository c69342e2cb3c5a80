#pragma once
// Per-voxel key cells and queue flags shared by concurrent relaxations. Host systems (CPP, OMP, TBB)
// use the GCC/Clang __atomic builtins on plain memory; device code (nvcc, __CUDA_ARCH__) uses the
// CUDA atomics. Every store that publishes a key is followed by a sequentially consistent (or
// fenced) flag operation, and every expansion clears its flag before it loads its key, so a key that
// is lowered while its voxel is being expanded always re-queues the voxel.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/key.hpp>

#include <cstdint>

namespace geovoronoi::thrust::detail {

/// Per-voxel flag word. Bits 0-1: queue state (not queued, in the far pile, in the near list).
/// Bit 2: the voxel has been expanded before (set by its first expansion, never cleared in a run).
/// Bit 3: suspect label (see expand_fn): the label repair pass starts from these voxels.
using flag_t = std::uint32_t;
inline constexpr flag_t idle = 0;
inline constexpr flag_t queued_far = 1;
inline constexpr flag_t queued_near = 2;
inline constexpr flag_t state_mask = 3;
inline constexpr flag_t expanded_bit = 4;
inline constexpr flag_t suspect_bit = 8;

GEOVORONOI_HOST_DEVICE inline flag_t flag_load(const flag_t* f) noexcept {
#ifdef __CUDA_ARCH__
  return *static_cast<const volatile flag_t*>(f);
#else
  return __atomic_load_n(f, __ATOMIC_SEQ_CST);
#endif
}

GEOVORONOI_HOST_DEVICE inline bool flag_cas(flag_t* f, flag_t expect, flag_t want) noexcept {
#ifdef __CUDA_ARCH__
  return atomicCAS(f, expect, want) == expect;
#else
  return __atomic_compare_exchange_n(f, &expect, want, false, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST);
#endif
}

/// Start of an expansion: clears the queue state and sets expanded_bit, atomically (neighbours may be
/// re-queuing the voxel at the same time); returns the previous word. Sequentially consistent and
/// done before the voxel's key is loaded, so a later drop of the key re-queues the voxel.
GEOVORONOI_HOST_DEVICE inline flag_t flag_begin_expansion(flag_t* f) noexcept {
  // one exchange; a suspect mark set before it is put back (one set after it lands on the new word,
  // and a neighbour's compare-and-swap that raced with the put-back retries)
#ifdef __CUDA_ARCH__
  const flag_t old = atomicExch(f, expanded_bit);
  if (old & suspect_bit) atomicOr(f, suspect_bit);
  __threadfence();
#else
  const flag_t old = __atomic_exchange_n(f, expanded_bit, __ATOMIC_SEQ_CST);
  if (old & suspect_bit) __atomic_fetch_or(f, suspect_bit, __ATOMIC_SEQ_CST);
#endif
  return old;
}

/// Moves the queue state to @p to if the current state satisfies @p from (other bits kept); true
/// when this call made the change.
template <class From>
GEOVORONOI_HOST_DEVICE inline bool flag_transition(flag_t* f, From from, flag_t to) noexcept {
  for (;;) {
    const flag_t cur = flag_load(f);
    if (!from(cur & state_mask)) return false;
    if (flag_cas(f, cur, (cur & ~state_mask) | to)) return true;
  }
}

struct from_idle {
  GEOVORONOI_HOST_DEVICE bool operator()(flag_t s) const noexcept { return s == idle; }
};
struct from_far {
  GEOVORONOI_HOST_DEVICE bool operator()(flag_t s) const noexcept { return s == queued_far; }
};
struct from_not_near {
  GEOVORONOI_HOST_DEVICE bool operator()(flag_t s) const noexcept { return s != queued_near; }
};

/// Sets bit(s) @p b of the flag word.
GEOVORONOI_HOST_DEVICE inline void flag_set_bits(flag_t* f, flag_t b) noexcept {
#ifdef __CUDA_ARCH__
  atomicOr(f, b);
#else
  __atomic_fetch_or(f, b, __ATOMIC_RELAXED);
#endif
}

GEOVORONOI_HOST_DEVICE inline void publish_fence() noexcept {
#ifdef __CUDA_ARCH__
  __threadfence();
#endif
}

/// Set a shared error flag (any thread, any system).
GEOVORONOI_HOST_DEVICE inline void raise(int* e) noexcept {
#ifdef __CUDA_ARCH__
  atomicExch(e, 1);
#else
  __atomic_store_n(e, 1, __ATOMIC_RELAXED);
#endif
}

template <class T>
struct key_cell;

/// float: the packed 64-bit key, lowered with one atomic min (a CAS loop on the host).
template <>
struct key_cell<float> {
  using kt = geovoronoi::detail::search::key_traits<float>;
  using key_type = kt::key_type;
  std::uint64_t bits;

  static constexpr key_cell make(key_type k) noexcept { return key_cell{k}; }
  GEOVORONOI_HOST_DEVICE static key_type load(const key_cell* c) noexcept {
#ifdef __CUDA_ARCH__
    return *reinterpret_cast<const volatile unsigned long long*>(&c->bits);
#else
    return __atomic_load_n(&c->bits, __ATOMIC_SEQ_CST);
#endif
  }
  /// Store @p k if it is strictly smaller; true when it was stored.
  GEOVORONOI_HOST_DEVICE static bool lower(key_cell* c, key_type k) noexcept {
#ifdef __CUDA_ARCH__
    const unsigned long long old = atomicMin(reinterpret_cast<unsigned long long*>(&c->bits), (unsigned long long)k);
    return k < old;
#else
    key_type cur = __atomic_load_n(&c->bits, __ATOMIC_RELAXED);
    while (k < cur)
      if (__atomic_compare_exchange_n(&c->bits, &cur, k, true, __ATOMIC_SEQ_CST, __ATOMIC_RELAXED)) return true;
    return false;
#endif
  }
};

/// double: the 96-bit key does not fit one portable atomic, so each cell carries a small spin lock.
template <>
struct key_cell<double> {
  using kt = geovoronoi::detail::search::key_traits<double>;
  using key_type = kt::key_type;
  std::uint64_t d;
  std::uint32_t l;
  std::uint32_t lock;

  static constexpr key_cell make(key_type k) noexcept { return key_cell{k.d, k.l, 0u}; }
  GEOVORONOI_HOST_DEVICE static void acquire(key_cell* c) noexcept {
#ifdef __CUDA_ARCH__
    while (atomicCAS(&c->lock, 0u, 1u) != 0u) {
    }
    __threadfence();
#else
    while (__atomic_exchange_n(&c->lock, 1u, __ATOMIC_SEQ_CST) != 0u)
      while (__atomic_load_n(&c->lock, __ATOMIC_RELAXED) != 0u) {
      }
#endif
  }
  GEOVORONOI_HOST_DEVICE static void release(key_cell* c) noexcept {
#ifdef __CUDA_ARCH__
    __threadfence();
    atomicExch(&c->lock, 0u);
#else
    __atomic_store_n(&c->lock, 0u, __ATOMIC_SEQ_CST);
#endif
  }
  GEOVORONOI_HOST_DEVICE static key_type load(const key_cell* cc) noexcept {
    key_cell* c = const_cast<key_cell*>(cc);
    acquire(c);
    key_type k{static_cast<volatile std::uint64_t&>(c->d), static_cast<volatile std::uint32_t&>(c->l)};
    release(c);
    return k;
  }
  GEOVORONOI_HOST_DEVICE static bool lower(key_cell* c, key_type k) noexcept {
    acquire(c);
    const key_type cur{static_cast<volatile std::uint64_t&>(c->d), static_cast<volatile std::uint32_t&>(c->l)};
    const bool better = k < cur;
    if (better) {
      static_cast<volatile std::uint64_t&>(c->d) = k.d;
      static_cast<volatile std::uint32_t&>(c->l) = k.l;
    }
    release(c);
    return better;
  }
};

}  // namespace geovoronoi::thrust::detail
