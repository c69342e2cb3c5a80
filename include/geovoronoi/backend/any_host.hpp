#pragma once
/// @file backend/any_host.hpp
/// @brief any_host_policy<P>: any host backend policy (geovoronoi::seq, geovoronoi::thrust::par on
///        a host system) behind one type, for problems of type P.
///
/// Code templated on the backend policy is compiled once per policy type. The shape functions and
/// their update are such code, and the largest part of it does not depend on the backend: only the
/// solves, the host loop and the thread count do. A program that offers several host backends (the
/// geovoronoi tool, the Python package) can pass any_host_policy<P> instead of the backend's own
/// policy, and every call then compiles once per problem type whichever host backend runs it. The
/// backend's hooks are reached through one virtual call each (per solve, per host loop: never per
/// voxel), and the results are those of the wrapped policy, bit for bit.
///
/// @code
/// using problem_t = decltype(p);
/// const geovoronoi::any_host_policy<problem_t> any(use_thrust ? geovoronoi::any_host_policy<problem_t>(geovoronoi::thrust::par)
///                                                             : geovoronoi::any_host_policy<problem_t>(geovoronoi::seq));
/// auto w = geovoronoi::shape_functions(any, p, d, opt);   // compiled once for both backends
/// @endcode

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/hooks.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/result.hpp>

#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi {

namespace detail {
/// A non-owning reference to a callable of signature R(A...), valid while the callable lives.
template <class Signature>
class function_ref;
template <class R, class... A>
class function_ref<R(A...)> {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, function_ref>>>
  function_ref(F& f) noexcept  // NOLINT: implicit, like a reference
      : obj_(static_cast<void*>(std::addressof(f))), call_([](void* o, A... a) -> R {
          return (*static_cast<F*>(o))(std::forward<A>(a)...);
        }) {}
  R operator()(A... a) const { return call_(obj_, std::forward<A>(a)...); }

 private:
  void* obj_;
  R (*call_)(void*, A...);
};
}  // namespace detail

/**
 * @brief A host backend policy of any type, for problems of type @p P (see the file comment).
 *
 * @tparam P the problem type (geovoronoi::problem<...>) the policy is used with.
 *
 * Copies share the wrapped policy. It provides every hook of a host backend: dense, bounded and
 * sparse solves, insert-query, the host loop, the thread count, backend_with_threads, and
 * backend_queries_on_host (true: the wrapped backend's insert-queries run on the host).
 */
template <class P>
class any_host_policy {
 public:
  using backend_policy_tag = void;  ///< marks a backend policy (is_backend_policy)
  using problem_type = P;
  using value_type = typename P::value_type;

  /// Wraps @p policy (copied). @pre a backend policy whose insert-queries run on the host.
  template <class Policy, class = std::enable_if_t<!std::is_same_v<std::decay_t<Policy>, any_host_policy>>>
  explicit any_host_policy(const Policy& policy) : impl_(std::make_shared<const model<Policy>>(policy)) {
    static_assert(is_backend_policy_v<Policy>, "geovoronoi::any_host_policy: the argument must be a backend policy");
    static_assert(detail::hooks::queries_on_host<Policy>::value,
                  "geovoronoi::any_host_policy: the backend must run on the host (geovoronoi::seq, "
                  "geovoronoi::thrust::par on a host system); a device backend keeps its own policy type");
  }

 private:
  using T = value_type;
  using sources = std::vector<source<T>>;

  struct concept_t {
    virtual ~concept_t() = default;
    virtual diagram<T, P::dim> solve(const P& p, const sources& s, T radius, const detail::solve_control& ctl) const = 0;
    virtual sparse_solution<T> bounded(const P& p, const sources& s, T radius, const detail::solve_control& ctl) const = 0;
    virtual query_cells<T> insert_queries(const P& p, const diagram<T, P::dim>& d,
                                          const std::vector<index_t>& queries) const = 0;
    virtual void parallel_for(index_t n, detail::function_ref<void(index_t)> f) const = 0;
    virtual void with_threads(unsigned threads, detail::function_ref<void()> f) const = 0;
    virtual unsigned host_threads() const = 0;
  };

  template <class Policy>
  struct model final : concept_t {
    explicit model(const Policy& p) : policy(p) {}
    Policy policy;

    diagram<T, P::dim> solve(const P& p, const sources& s, T radius, const detail::solve_control& ctl) const override {
      static_assert(detail::hooks::has_solve<Policy, P>::value, "any_host_policy: the backend has no dense solve");
      if constexpr (detail::hooks::has_solve_control<Policy, P>::value) {
        return backend_solve(policy, p, s, radius, ctl);
      } else {
        ctl.report(0.0);
        auto d = backend_solve(policy, p, s, radius);
        ctl.report(1.0);
        return d;
      }
    }
    sparse_solution<T> bounded(const P& p, const sources& s, T radius, const detail::solve_control& ctl) const override {
      static_assert(detail::hooks::has_bounded<Policy, P>::value, "any_host_policy: the backend has no bounded solve");
      if constexpr (detail::hooks::has_bounded_control<Policy, P>::value) {
        return backend_bounded(policy, p, s, radius, ctl);
      } else {
        ctl.report(0.0);
        auto r = backend_bounded(policy, p, s, radius);
        ctl.report(1.0);
        return r;
      }
    }
    query_cells<T> insert_queries(const P& p, const diagram<T, P::dim>& d,
                                  const std::vector<index_t>& queries) const override {
      static_assert(detail::hooks::has_insert<Policy, P>::value, "any_host_policy: the backend has no insert-query");
      return backend_insert_queries(policy, p, d, queries);
    }
    void parallel_for(index_t n, detail::function_ref<void(index_t)> f) const override {
      detail::host_parallel_for(policy, n, f);
    }
    void with_threads(unsigned threads, detail::function_ref<void()> f) const override {
      detail::with_threads(policy, threads, [&] {
        f();
        return 0;
      });
    }
    unsigned host_threads() const override { return detail::host_threads(policy); }
  };

  std::shared_ptr<const concept_t> impl_;

  // ---- the hooks (found by argument-dependent lookup) ----------------------------------------------
  friend diagram<T, P::dim> backend_solve(const any_host_policy& a, const P& p, const sources& s, T radius,
                                          const detail::solve_control& ctl = {}) {
    return a.impl_->solve(p, s, radius, ctl);
  }
  friend sparse_solution<T> backend_bounded(const any_host_policy& a, const P& p, const sources& s, T radius,
                                            const detail::solve_control& ctl = {}) {
    return a.impl_->bounded(p, s, radius, ctl);
  }
  friend query_cells<T> backend_insert_queries(const any_host_policy& a, const P& p, const diagram<T, P::dim>& d,
                                               const std::vector<index_t>& queries) {
    return a.impl_->insert_queries(p, d, queries);
  }
  template <class F>
  friend void backend_host_parallel_for(const any_host_policy& a, index_t n, F&& f) {
    auto body = [&f](index_t i) { f(i); };
    a.impl_->parallel_for(n, body);
  }
  template <class F>
  friend decltype(auto) backend_with_threads(const any_host_policy& a, unsigned threads, F&& f) {
    using R = decltype(f());
    if constexpr (std::is_void_v<R>) {
      auto body = [&f] { f(); };
      a.impl_->with_threads(threads, body);
    } else {
      std::optional<R> r;
      auto body = [&] { r.emplace(f()); };
      a.impl_->with_threads(threads, body);
      return R(std::move(*r));
    }
  }
  friend unsigned backend_host_threads(const any_host_policy& a) { return a.impl_->host_threads(); }
  friend std::true_type backend_queries_on_host(const any_host_policy&) { return {}; }
};

}  // namespace geovoronoi
