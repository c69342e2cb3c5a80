#pragma once
// The concrete typed problems (typed_problem.hpp): the library's calls on one problem type P with one
// backend policy. Included only by the instance units (instances.cpp.in, cuda.cu), each of which also
// includes its backend's header and registers make_typed_problem_on<...> for its backend, distance
// type, dimension and cuts-or-not; everything else sees the virtual interface only.

#include "typed_problem.hpp"

#include <geovoronoi/backend/any_host.hpp>
#include <geovoronoi/backend/seq.hpp>

#include <memory>
#include <mutex>
#include <type_traits>
#include <utility>

namespace gvcli {

/// P (a library problem) on backend Policy. With HostShapeUpdate the shape-function updates run on
/// the host problem (seq) rather than on Policy: the CUDA backend's are host updates. On a host
/// backend the shape functions and the updates run through any_host_policy<P>, so that the host
/// backends of one instance unit share one compiled copy of them.
///
/// The updates are instantiated for problems with cuts only: a problem without cuts updates through
/// the same problem with an empty cut table (made when first needed), which has every edge of the
/// plain problem, so the update is the plain one's bit for bit, and the units without cuts compile
/// the solves alone.
template <class Policy, class P, bool HostShapeUpdate>
class typed_problem_on final : public typed_problem<typename P::value_type, P::dim> {
 public:
  using T = typename P::value_type;
  static constexpr int Dim = P::dim;
  using base = typed_problem<T, Dim>;
  static constexpr bool is_seq = std::is_same_v<Policy, gv::seq_t>;

  typed_problem_on(const problem_key& k, const P& p, std::unique_ptr<base> host)
      : base(k), p_(p), host_(std::move(host)) {}

  /// The policy the shape functions and the updates run on.
  static auto shape_policy() {
    if constexpr (gv::detail::hooks::queries_on_host<Policy>::value)
      return gv::any_host_policy<P>(Policy{});
    else
      return Policy{};
  }

  gv::diagram<T, Dim> voronoi(const std::vector<gv::coord<Dim>>& seeds, const gv::solve_options& opt) const override {
    return gv::voronoi(Policy{}, p_, seeds, opt);
  }
  gv::shape_weights<T, Dim> shape_functions(const gv::diagram<T, Dim>& d, const gv::shape_options& opt) const override {
    return gv::shape_functions(shape_policy(), p_, d, opt);
  }
  gv::point_weights<T> shape_functions_at(const gv::diagram<T, Dim>& d, const std::vector<gv::coord<Dim>>& points,
                                          const gv::shape_options& opt) const override {
    return gv::shape_functions_at(shape_policy(), p_, d, points, opt);
  }
  gv::update_stats update_in_place(gv::diagram<T, Dim>& d, const gv::change<Dim>& c) const override {
    if constexpr (!P::has_cuts)
      return with_empty_cuts().update_in_place(d, c);
    else if constexpr (is_seq)
      return gv::update_in_place(gv::seq, p_, d, c);
    else
      return host_->update_in_place(d, c);
  }
  gv::shape_update_stats update_shape_functions_in_place(const gv::diagram<T, Dim>& d_before,
                                                         const gv::diagram<T, Dim>& d_after, gv::shape_weights<T, Dim>& w,
                                                         const gv::change<Dim>& c,
                                                         const gv::shape_options& opt) const override {
    if constexpr (!P::has_cuts)
      return with_empty_cuts().update_shape_functions_in_place(d_before, d_after, w, c, opt);
    else if constexpr (HostShapeUpdate)
      return host_->update_shape_functions_in_place(d_before, d_after, w, c, opt);
    else
      return gv::update_shape_functions_in_place(shape_policy(), p_, d_before, d_after, w, c, opt);
  }
  gv::shape_update_stats update_shape_functions_at_in_place(const gv::diagram<T, Dim>& d_before,
                                                            const gv::diagram<T, Dim>& d_after, gv::point_weights<T>& w,
                                                            const gv::change<Dim>& c,
                                                            const gv::shape_options& opt) const override {
    if constexpr (!P::has_cuts)
      return with_empty_cuts().update_shape_functions_at_in_place(d_before, d_after, w, c, opt);
    else if constexpr (HostShapeUpdate)
      return host_->update_shape_functions_at_in_place(d_before, d_after, w, c, opt);
    else
      return gv::update_shape_functions_at_in_place(shape_policy(), p_, d_before, d_after, w, c, opt);
  }
  backend_id shape_update_backend() const noexcept override {
    return HostShapeUpdate ? backend_id::seq : this->key().backend;
  }

 private:
  /// This problem with an empty cut table, for the updates of a problem without cuts.
  const base& with_empty_cuts() const {
    std::call_once(empty_cuts_once_, [this] {
      empty_cuts_ = std::make_unique<gv::cut_table>(gv::cut_set<Dim>(p_.geometry, typename P::connectivity_type{}));
      problem_key k = this->key();
      k.cuts = true;
      with_cuts_ = make_typed_problem<T, Dim>(k, gv::image_view<const T, Dim>(p_.geometry, p_.field), empty_cuts_.get());
    });
    return *with_cuts_;
  }

  P p_;
  std::unique_ptr<base> host_;  ///< the seq problem of the same key (null on seq)
  mutable std::once_flag empty_cuts_once_;
  mutable std::unique_ptr<gv::cut_table> empty_cuts_;
  mutable std::unique_ptr<base> with_cuts_;
};

/// The maker an instance unit registers (problem_maker): the problem of @p key on Policy, in T and Dim,
/// with the cut edges of @p cuts when Cuts. The one place where the key's names become types.
template <class Policy, class T, int Dim, bool Cuts, bool HostShapeUpdate = false>
std::unique_ptr<typed_problem<T, Dim>> make_typed_problem_on(const problem_key& key, gv::image_view<const T, Dim> field,
                                                             const gv::cut_table* cuts,
                                                             std::unique_ptr<typed_problem<T, Dim>> host) {
  std::unique_ptr<typed_problem<T, Dim>> out;
  with_metric(key.metric, [&](auto metric) {
    with_connectivity<Dim>(key.connectivity, [&](auto conn) {
      const auto p = gv::make_problem(field.geometry(), field, metric, conn);
      if constexpr (Cuts) {
        const auto pc = gv::with_cuts(p, *cuts);
        out = std::make_unique<typed_problem_on<Policy, std::decay_t<decltype(pc)>, HostShapeUpdate>>(key, pc,
                                                                                                     std::move(host));
      } else {
        out = std::make_unique<typed_problem_on<Policy, std::decay_t<decltype(p)>, HostShapeUpdate>>(key, p,
                                                                                                    std::move(host));
      }
    });
  });
  return out;
}

}  // namespace gvcli
