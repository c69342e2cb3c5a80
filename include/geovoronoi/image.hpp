#pragma once
/// @file image.hpp
/// @brief An owning host volume (image) and its non-owning, trivially copyable view (image_view).

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>

#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi {

/**
 * @brief Non-owning view of a voxel volume: a grid and a pointer to grid.size() values, x fastest.
 *
 * Trivially copyable, so it can be passed to kernels by value. T may be const.
 */
template <class T, int Dim>
class image_view {
 public:
  using value_type = std::remove_cv_t<T>;
  image_view() = default;
  GEOVORONOI_HOST_DEVICE image_view(const grid<Dim>& g, T* data) noexcept : grid_(g), data_(data) {}
  /// A view of non-const values converts to a view of const values.
  template <class U, class = std::enable_if_t<std::is_same_v<const U, T> && !std::is_const_v<U>>>
  GEOVORONOI_HOST_DEVICE image_view(const image_view<U, Dim>& other) noexcept
      : grid_(other.geometry()), data_(other.data()) {}

  GEOVORONOI_HOST_DEVICE const grid<Dim>& geometry() const noexcept { return grid_; }
  GEOVORONOI_HOST_DEVICE T* data() const noexcept { return data_; }
  GEOVORONOI_HOST_DEVICE index_t size() const noexcept { return grid_.size(); }
  GEOVORONOI_HOST_DEVICE T& operator[](index_t v) const noexcept { return data_[v]; }
  GEOVORONOI_HOST_DEVICE T& operator()(const coord<Dim>& c) const noexcept { return data_[grid_.index(c)]; }
  GEOVORONOI_HOST_DEVICE T* begin() const noexcept { return data_; }
  GEOVORONOI_HOST_DEVICE T* end() const noexcept { return data_ + size(); }

 private:
  grid<Dim> grid_{};
  T* data_ = nullptr;
};

/**
 * @brief An owning host volume: a grid and grid.size() values in a std::vector, x fastest.
 *
 * @code
 * geovoronoi::image<float, 3> stiffness(geovoronoi::grid<3>({64, 64, 64}), 1.0f);
 * stiffness({10, 20, 30}) = 10.0f;
 * @endcode
 */
template <class T, int Dim>
class image {
 public:
  using value_type = T;
  image() = default;
  /// A volume over @p g with every value set to @p fill.
  explicit image(const grid<Dim>& g, const T& fill = T{}) : grid_(g), data_(static_cast<std::size_t>(g.size()), fill) {}
  /// Adopt @p values; throws std::invalid_argument if their count differs from g.size().
  image(const grid<Dim>& g, std::vector<T> values) : grid_(g), data_(std::move(values)) {
    if (static_cast<index_t>(data_.size()) != g.size())
      throw std::invalid_argument("geovoronoi::image: " + std::to_string(data_.size()) +
                                  " values given for a grid of " + std::to_string(g.size()) + " voxels");
  }

  const grid<Dim>& geometry() const noexcept { return grid_; }
  index_t size() const noexcept { return static_cast<index_t>(data_.size()); }
  bool empty() const noexcept { return data_.empty(); }
  T* data() noexcept { return data_.data(); }
  const T* data() const noexcept { return data_.data(); }
  T& operator[](index_t v) noexcept { return data_[static_cast<std::size_t>(v)]; }
  const T& operator[](index_t v) const noexcept { return data_[static_cast<std::size_t>(v)]; }
  T& operator()(const coord<Dim>& c) noexcept { return (*this)[grid_.index(c)]; }
  const T& operator()(const coord<Dim>& c) const noexcept { return (*this)[grid_.index(c)]; }
  auto begin() noexcept { return data_.begin(); }
  auto end() noexcept { return data_.end(); }
  auto begin() const noexcept { return data_.begin(); }
  auto end() const noexcept { return data_.end(); }
  std::vector<T>& values() noexcept { return data_; }
  const std::vector<T>& values() const noexcept { return data_; }

  image_view<T, Dim> view() & noexcept { return {grid_, data_.data()}; }
  image_view<const T, Dim> view() const& noexcept { return {grid_, data_.data()}; }
  /// A view of a temporary image would dangle once the statement ends.
  image_view<T, Dim> view() && = delete;
  image_view<const T, Dim> view() const&& = delete;
  operator image_view<const T, Dim>() const noexcept { return {grid_, data_.data()}; }

 private:
  grid<Dim> grid_{};
  std::vector<T> data_;
};

}  // namespace geovoronoi
