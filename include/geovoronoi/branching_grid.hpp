#pragma once
/// @file branching_grid.hpp
/// @brief Non-manifold ("branching") coarse grids: one node per connected component of the fine
///        material in each coarse cell, so that parts closer than a coarse cell (fingers, the lips of
///        a thin cut) stay apart; the geodesic Voronoi diagram on them and its picture on the fine grid.
///
/// On a regular coarse grid two parts that share a cell are glued: the geodesic distance between them
/// is one step. A branching grid (Nesme, Kry, Jeřábková, Faure 2009) keeps, in each coarse cell, one
/// copy per connected component of the fine material inside it, and links copies of neighbouring cells
/// only where their fine material touches across the cells' border. See docs/branching.md.
///
/// @code
/// auto fine = geovoronoi::phantom::fingers(geovoronoi::grid<3>({64, 48, 16}));
/// auto bg = geovoronoi::make_branching_grid(fine, 4, geovoronoi::connectivity<26>{});
/// auto p = geovoronoi::make_problem(bg, geovoronoi::min_stiffness{});
/// auto d = geovoronoi::voronoi(geovoronoi::seq, p, std::vector<geovoronoi::coord<3>>{{2, 40, 8}, {61, 40, 8}});
/// auto picture = geovoronoi::paint_fine(bg, d);   // distance and label images on the fine grid
/// @endcode

#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/detail/branching/build.hpp>
#include <geovoronoi/detail/hooks.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/search/parents.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>
#include <geovoronoi/voronoi.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi {

/// Options of make_branching_grid().
struct branching_options {
  /// How a copy's stiffness is reduced from its fine voxels' values (see stiffness_reduction).
  stiffness_reduction reduction = stiffness_reduction::mean;
};

/**
 * @brief A branching (non-manifold) coarse grid over a fine voxel image.
 *
 * - coarse(): the coarse grid<Dim>: extents ceil(fine extent / factor) (a last, partial cell is
 *   padded with empty material), spacing = fine spacing x factor, the fine direction, and each
 *   cell's centre at the centre of its factor^Dim fine voxels (padding included).
 * - copies: per coarse cell c, copies cell_begin()[c] .. cell_begin()[c+1]-1, one per connected
 *   component (under connectivity<N>) of the cell's fine material (fine value > 0; NaN is not
 *   material). Copies are numbered by cell index, then by the lowest fine voxel index of the
 *   component (copy_voxel()): a strict order, independent of anything but the image.
 * - links: copy a's links are entries link_begin()[a] .. link_begin()[a+1]-1 of link_copy() (the
 *   other copy, increasing) and link_dir() (the index k of the coarse stencil's offset from a's cell
 *   to the other's; the edge has the coarse stencil's length k). Two copies of different cells are
 *   linked when some fine voxel of one and some fine voxel of the other are neighbours under
 *   connectivity<N>; their cells are then neighbours under connectivity<N> too. Links are symmetric.
 * - fine_copy(): per fine voxel its copy, -1 outside the material.
 * - stiffness(): per copy, the reduction of its fine values (branching_options::reduction).
 *
 * With factor 1 the copies are the material voxels in index order and the links the stencil's
 * edges between them: the regular grid, on which voronoi() gives the regular solve's bits.
 *
 * @tparam Dim 2 or 3.  @tparam T the field type (float or double).  @tparam N the connectivity.
 */
template <int Dim, class T = float, int N = (Dim == 2 ? 8 : 26)>
class branching_grid {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>,
                "geovoronoi::branching_grid: the field type must be float or double");
  static_assert(connectivity<N>::dim == Dim, "geovoronoi::branching_grid: connectivity<N> does not match Dim");

 public:
  using value_type = T;
  using connectivity_type = connectivity<N>;
  static constexpr int dim = Dim;
  static constexpr int neighbours = N;

  branching_grid() = default;
  /// Adopts the arrays the builder made (make_branching_grid()).
  explicit branching_grid(detail::branching::parts<Dim, T>&& p) : p_(std::move(p)) {}

  /// The fine grid (the image's).
  const grid<Dim>& fine() const noexcept { return p_.fine; }
  /// The coarse grid.
  const grid<Dim>& coarse() const noexcept { return p_.coarse; }
  /// Fine voxels per coarse cell along each axis.
  int factor() const noexcept { return p_.factor; }
  /// Number of copies (the graph's nodes).
  index_t copies() const noexcept { return index_t(p_.copy_cell.size()); }
  /// Number of links (each counted once per direction).
  index_t links() const noexcept { return index_t(p_.link_copy.size()); }
  /// coarse().size() + 1 entries: the copies of cell c are cell_begin()[c] .. cell_begin()[c+1]-1.
  const std::vector<index_t>& cell_begin() const noexcept { return p_.cell_begin; }
  /// The coarse cell of each copy.
  const std::vector<index_t>& copy_cell() const noexcept { return p_.copy_cell; }
  /// The lowest fine voxel index of each copy (which orders the copies of a cell).
  const std::vector<index_t>& copy_voxel() const noexcept { return p_.copy_voxel; }
  /// The number of fine voxels of each copy.
  const std::vector<index_t>& voxel_count() const noexcept { return p_.voxel_count; }
  /// copies() + 1 entries: the links of copy a are link_begin()[a] .. link_begin()[a+1]-1.
  const std::vector<index_t>& link_begin() const noexcept { return p_.link_begin; }
  /// The other copy of each link (increasing within a copy's links).
  const std::vector<index_t>& link_copy() const noexcept { return p_.link_copy; }
  /// The coarse stencil direction (connectivity<N>'s offset index) of each link.
  const std::vector<std::uint8_t>& link_dir() const noexcept { return p_.link_dir; }
  /// Per fine voxel its copy, -1 outside the material.
  const image<index_t, Dim>& fine_copy() const noexcept { return p_.fine_copy; }
  /// Per copy its stiffness.
  const std::vector<T>& stiffness() const noexcept { return p_.stiffness; }

  /// The arrays the searches walk (detail/search/topology.hpp's link_walker), beside the public CSR.
  const detail::branching::parts<Dim, T>& walk_parts() const noexcept { return p_; }

  /// "copy 12 (coarse cell (1, 2, 0), lowest fine voxel (4, 8, 1))", for messages.
  std::string copy_text(index_t c) const {
    return "copy " + std::to_string(c) + " (coarse cell " +
           to_string<Dim>(p_.coarse.coords(p_.copy_cell[std::size_t(c)])) + ", lowest fine voxel " +
           to_string<Dim>(p_.fine.coords(p_.copy_voxel[std::size_t(c)])) + ")";
  }

 private:
  detail::branching::parts<Dim, T> p_;
};

/**
 * @brief Builds the branching grid of a fine image.
 *
 * @param fine   the fine field: material where the value is > 0 (the stiffness metrics' domain rule);
 *               its values also give the copies' stiffness.
 * @param factor fine voxels per coarse cell along each axis, >= 1.
 * @param conn   the one connectivity used for the components inside a cell, for the fine contacts
 *               that link copies, and for the coarse stencil the links live on.
 * @param opt    the stiffness reduction.
 * @throws std::invalid_argument naming the problem: a factor < 1, an empty image, no material, a
 *         coarse grid that is not valid (its spacing overflows). The copies cannot outnumber the
 *         fine voxels, so their count always fits index_t.
 *
 * @code
 * auto bg = geovoronoi::make_branching_grid(fine, 4, geovoronoi::connectivity<6>{});
 * @endcode
 */
template <class T, int Dim, int N = (Dim == 2 ? 8 : 26)>
branching_grid<Dim, T, N> make_branching_grid(const image<T, Dim>& fine, int factor, connectivity<N> = {},
                                              const branching_options& opt = {}) {
  return branching_grid<Dim, T, N>(
      detail::branching::build<Dim, T, N>(image_view<const T, Dim>(fine.geometry(), fine.data()), factor, opt.reduction));
}

/**
 * @brief The geodesic problem on a branching grid: a trivially copyable view of its copy graph
 *        (per-copy stiffness, links) with a metric and the coarse stencil.
 *
 * The weight of the link a -> b of direction k is metric(edges.length[k], stiffness[a], stiffness[b]),
 * the edge weight of the regular grid's solvers (detail/search/relax.hpp) between two voxels of those
 * values at the coarse stencil's length. The branching grid must outlive the problem.
 */
template <class T, int Dim, class Metric, int N>
struct branching_problem {
  static_assert(detail::is_metric_v<Metric, T>,
                "geovoronoi::branching_problem: Metric must be callable as T(T length, T from, T to) const");
  static_assert(std::is_trivially_copyable_v<Metric>, "geovoronoi::branching_problem: Metric must be trivially copyable");
  using value_type = T;
  using metric_type = Metric;
  using connectivity_type = connectivity<N>;
  using cuts_type = no_cuts;
  /// The engines walk the links (detail/search/topology.hpp).
  using walker_type = detail::search::link_walker;
  static constexpr int dim = Dim;
  static constexpr int neighbours = N;
  static constexpr bool has_cuts = false;

  // The searches number the copies by slots (detail/branching/build.hpp): slot c is the first copy
  // of cell c, so that most links are found like a grid's neighbours; the front end maps seeds and
  // results between copies and slots.
  const T* field = nullptr;  ///< per slot its copy's stiffness (NaN for an empty cell)
  Metric metric{};
  stencil<T, Dim, N> edges{};  ///< the coarse stencil
  const detail::search::copy_walk* walk = nullptr;  ///< per slot what the walk reads (link_walker)
  const std::uint32_t* walk_bits = nullptr;          ///< per slot its mask and row bit (link_walker)
  const index_t* walk_extra_node = nullptr;
  const std::uint8_t* walk_extra_dir = nullptr;
  const index_t* copy_of_slot = nullptr;
  const index_t* slot_of_copy = nullptr;
  index_t slots = 0;
  index_t cells = 0;      ///< coarse cells: slots below are their cell's first copy
  index_t max_links = 0;  ///< the most links of one copy
  const branching_grid<Dim, T, N>* owner = nullptr;

  /// Number of nodes the searches see (slots).
  GEOVORONOI_HOST_DEVICE index_t nodes() const noexcept { return slots; }
  /// Whether slot @p s holds a copy in the metric's domain.
  GEOVORONOI_HOST_DEVICE bool inside(index_t s) const noexcept { return detail::inside<Metric>(field[s]); }
  /// The parent rule's order of slot @p s: its copy's index.
  index_t rank(index_t s) const noexcept { return copy_of_slot[s]; }
  /// The branching grid.
  const branching_grid<Dim, T, N>& grid_of() const noexcept { return *owner; }
  /// Slot @p s named for messages (by its copy).
  std::string node_text(index_t s) const { return owner->copy_text(copy_of_slot[s]); }

  /// This problem with the arrays its walk and relaxation read (field, walk, walk_bits, the extra rows)
  /// replaced by copy(pointer, count), which returns a pointer to a copy of those count elements: how
  /// a backend moves the graph to device memory (the Thrust backend on the CUDA system). The members
  /// only the host reads (copy_of_slot, slot_of_copy, owner) stay as they are.
  template <class Copy>
  branching_problem with_walk_arrays(Copy&& copy) const {
    const auto& w = owner->walk_parts();
    branching_problem q = *this;
    q.field = copy(field, w.slot_stiffness.size());
    q.walk = copy(walk, w.walk.size());
    q.walk_bits = copy(walk_bits, w.walk_bits.size());
    q.walk_extra_node = copy(walk_extra_node, w.walk_extra_node.size());
    q.walk_extra_dir = copy(walk_extra_dir, w.walk_extra_dir.size());
    return q;
  }
};

/**
 * @brief The problem on branching grid @p bg with metric @p metric (its stencil: the coarse grid's).
 * @throws std::invalid_argument when an edge of the coarse stencil is 0 or infinite in T.
 */
template <int Dim, class T, int N, class Metric = min_stiffness>
branching_problem<T, Dim, Metric, N> make_problem(const branching_grid<Dim, T, N>& bg, Metric metric = {}) {
  detail::check_edge_lengths<T, Dim, N>(bg.coarse());
  branching_problem<T, Dim, Metric, N> p;
  const auto& w = bg.walk_parts();
  p.field = w.slot_stiffness.data();
  p.metric = metric;
  p.edges = stencil<T, Dim, N>(bg.coarse(), connectivity<N>{});
  p.walk = w.walk.data();
  p.walk_bits = w.walk_bits.data();
  p.walk_extra_node = w.walk_extra_node.data();
  p.walk_extra_dir = w.walk_extra_dir.data();
  p.copy_of_slot = w.copy_of_slot.data();
  p.slot_of_copy = w.slot_of_copy.data();
  p.slots = index_t(w.copy_of_slot.size());
  p.cells = bg.coarse().size();
  const auto& lb = bg.link_begin();
  for (index_t c = 0; c < bg.copies(); ++c) p.max_links = std::max(p.max_links, lb[std::size_t(c) + 1] - lb[std::size_t(c)]);
  p.owner = &bg;
  return p;
}
/// A temporary branching grid would be destroyed while the problem still points at it.
template <int Dim, class T, int N, class... Rest>
void make_problem(branching_grid<Dim, T, N>&&, Rest&&...) = delete;

/// The diagram of a branching problem: per copy its distance, label and (on request) parent copy;
/// seeds holds each seed's copy. See node_diagram.
template <class T>
using branching_diagram = node_diagram<T>;

namespace detail::branching {
/// The copy of seed @p i given as a fine voxel, or as a world point (nearest fine voxel centre).
template <class P, class C>
index_t seed_copy(const P& p, const C& c, std::size_t i) {
  const auto& bg = p.grid_of();
  constexpr int Dim = P::dim;
  coord<Dim> v{};
  const std::string name = "geovoronoi: seed " + std::to_string(i);
  if constexpr (std::is_floating_point_v<std::decay_t<decltype(c[0])>>) {
    point<Dim> x{};
    for (int a = 0; a < Dim; ++a) x[a] = double(c[a]);
    try {
      v = bg.fine().checked_nearest_voxel(x);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(name + ": " + e.what());
    }
  } else {
    for (int a = 0; a < Dim; ++a) v[a] = index_t(c[a]);
    if (!bg.fine().contains(v))
      throw std::invalid_argument(name + " at " + to_string<Dim>(v) + " lies outside the fine grid");
  }
  const index_t copy = bg.fine_copy()(v);
  if (copy < 0)
    throw std::invalid_argument(name + " at fine voxel " + to_string<Dim>(v) +
                                " lies in empty material (its fine value is not > 0), where the branching grid has "
                                "no copy");
  if (!p.inside(p.slot_of_copy[copy]))
    throw std::invalid_argument(name + " at fine voxel " + to_string<Dim>(v) + " lies in " + bg.copy_text(copy) +
                                ", whose stiffness " + std::to_string(double(bg.stiffness()[std::size_t(copy)])) +
                                " is outside the metric's domain");
  return copy;
}
}  // namespace detail::branching

/**
 * @brief Geodesic Voronoi diagram of @p seeds on a branching grid: every copy's distance to its
 *        nearest seed and that seed's index, ties going to the lowest index.
 *
 * The same engine and relaxation rule as the regular solves (and the same contract: every backend
 * returns the same bits). Backends: geovoronoi::seq and the Thrust backend on host systems.
 *
 * @param seeds a range of fine voxel coordinates (coord<Dim>) or of world points (point<Dim>, each
 *              taken to its nearest fine voxel centre); each is mapped to the copy holding it.
 * @param opt   parent (per copy), radius bound, progress callback, host threads.
 * @throws std::invalid_argument if the list is empty, or a seed lies outside the fine grid, in empty
 *         material, or in the same copy as another seed (the message names the seeds and the copy).
 *
 * @code
 * auto d = geovoronoi::voronoi(geovoronoi::seq, p, std::vector<geovoronoi::coord<3>>{{2, 40, 8}});
 * float far = d.distance[bg.fine_copy()({5, 40, 8})];
 * @endcode
 */
template <class Policy, class T, int Dim, class Metric, int N, class Seeds>
branching_diagram<T> voronoi(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p, const Seeds& seeds,
                             const solve_options& opt = {}) {
  detail::require_policy<Policy>();
  using P = branching_problem<T, Dim, Metric, N>;
  static_assert(!is_backend_policy_v<Policy> || detail::hooks::has_solve_nodes<Policy, P>::value,
                "geovoronoi: this backend provides no solve on branching grids (backend_solve_nodes)");
  std::vector<source<T>> s;
  for (const auto& c : seeds) {
    if (s.size() >= std::size_t(std::numeric_limits<label_t>::max()))
      throw std::invalid_argument("geovoronoi: too many seeds for 32-bit labels");
    s.push_back({detail::branching::seed_copy(p, c, s.size()), T(0), label_t(s.size())});
  }
  if (s.empty()) throw std::invalid_argument("geovoronoi: the seed list is empty");
  std::vector<std::pair<index_t, std::size_t>> order(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) order[i] = {s[i].voxel, i};
  std::sort(order.begin(), order.end());
  for (std::size_t i = 1; i < order.size(); ++i)
    if (order[i].first == order[i - 1].first)
      throw std::invalid_argument("geovoronoi: seeds " + std::to_string(order[i - 1].second) + " and " +
                                  std::to_string(order[i].second) + " lie in the same " +
                                  p.grid_of().copy_text(order[i].first) + " of the branching grid");
  const T radius = detail::checked_radius<T>(opt);
  const auto ctl = detail::solve_control::of(opt);
  std::vector<source<T>> at_slots = s;
  for (auto& x : at_slots) x.voxel = p.slot_of_copy[x.voxel];
  const branching_diagram<T> by_slot = detail::with_threads(policy, opt.threads, [&] {
    if constexpr (detail::hooks::has_solve_nodes<Policy, P>::value)
      return backend_solve_nodes(policy, p, at_slots, radius, ctl);
    else
      return branching_diagram<T>{};
  });
  const auto copies = std::size_t(p.grid_of().copies());
  branching_diagram<T> d;
  d.distance.resize(copies);
  d.label.resize(copies);
  for (std::size_t a = 0; a < copies; ++a) {
    d.distance[a] = by_slot.distance[std::size_t(p.slot_of_copy[a])];
    d.label[a] = by_slot.label[std::size_t(p.slot_of_copy[a])];
  }
  for (const auto& x : s) d.seeds.push_back(x.voxel);
  if (opt.with_parent) {
    std::vector<index_t> parent(by_slot.size(), no_index);
    detail::search::parents_into(p, by_slot.distance.data(), by_slot.label.data(), at_slots, parent.data());
    d.parent.assign(copies, no_index);
    for (std::size_t a = 0; a < copies; ++a) {
      const index_t ps = parent[std::size_t(p.slot_of_copy[a])];
      d.parent[a] = ps < 0 ? no_index : p.copy_of_slot[ps];
    }
  }
  return d;
}

/**
 * @brief The diagram of a branching grid painted on its fine grid: each fine voxel shows its copy's
 *        distance and label; +inf and -1 outside the material. parent and seeds are left empty.
 * @throws std::invalid_argument if @p d does not have one entry per copy of @p bg.
 */
template <int Dim, class T, int N>
diagram<T, Dim> paint_fine(const branching_grid<Dim, T, N>& bg, const branching_diagram<T>& d) {
  if (index_t(d.distance.size()) != bg.copies() || index_t(d.label.size()) != bg.copies())
    throw std::invalid_argument("geovoronoi::paint_fine: the diagram has " + std::to_string(d.distance.size()) +
                                " entries but the branching grid has " + std::to_string(bg.copies()) + " copies");
  diagram<T, Dim> out;
  out.distance = image<T, Dim>(bg.fine(), std::numeric_limits<T>::infinity());
  out.label = image<label_t, Dim>(bg.fine(), no_label);
  const index_t* fc = bg.fine_copy().data();
  for (index_t v = 0; v < bg.fine().size(); ++v)
    if (fc[v] >= 0) {
      out.distance[v] = d.distance[std::size_t(fc[v])];
      out.label[v] = d.label[std::size_t(fc[v])];
    }
  return out;
}

}  // namespace geovoronoi
