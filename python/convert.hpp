#pragma once
// Conversions between numpy arrays / Python objects and the library's types, shared by
// the binding files of the `ballagg` module.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/config/config.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/spin.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// The dimension of an (n, D) array of points (D = 2 or 3); throws ValueError otherwise.
inline int dimension_of(const DoubleArray& points, const char* what = "positions") {
  if (points.ndim() != 2 || (points.shape(1) != 2 && points.shape(1) != 3))
    throw py::value_error(std::string(what) + " must be an (n, 2) or (n, 3) array");
  return static_cast<int>(points.shape(1));
}

template <int D>
std::vector<Vec<D>> to_points(const DoubleArray& a, const char* what = "positions") {
  if (dimension_of(a, what) != D) throw py::value_error(std::string(what) + ": wrong dimension");
  const auto n = static_cast<std::size_t>(a.shape(0));
  std::vector<Vec<D>> out(n);
  const double* p = a.data();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < D; ++k) out[i][k] = p[i * D + k];
  return out;
}

template <int D>
py::array_t<double> from_points(const std::vector<Vec<D>>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(D)});
  double* p = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < D; ++k) p[i * D + k] = v[i][k];
  return a;
}

// Angular velocities, one per sphere: (n, 3) in 3D, (n,) in 2D (a scalar spin about the
// normal of the plane).
template <int D>
py::array_t<double> from_spins(const std::vector<Spin<D>>& w) {
  if constexpr (D == 3) {
    return from_points<3>(w);
  } else {
    std::vector<double> z(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) z[i] = w[i][0];
    py::array_t<double> a(static_cast<py::ssize_t>(z.size()));
    std::copy(z.begin(), z.end(), a.mutable_data());
    return a;
  }
}

template <int D>
py::array_t<double> from_vec(const Vec<D>& v) {
  return from_points<D>(std::vector<Vec<D>>{v}).reshape({D});
}

template <class T, class A>
std::vector<T> to_vector(const A& a, std::size_t n, const char* what) {
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw py::value_error(std::string(what) + " must be a 1-d array of length " + std::to_string(n));
  return std::vector<T>(a.data(), a.data() + n);
}

template <class T>
py::array_t<T> from_vector(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

template <int D>
Box<D> make_box(double length, bool periodic) {
  if (!(length > 0.0)) throw py::value_error("box_length must be > 0");
  return Box<D>{length, periodic ? Boundary::periodic : Boundary::walls};
}

inline py::object fit_object(const std::optional<LinearFit>& f) {
  if (!f) return py::none();
  py::dict d;
  d["slope"] = f->slope;
  d["intercept"] = f->intercept;
  d["slope_error"] = f->slope_error;
  d["intercept_error"] = f->intercept_error;
  d["points"] = f->points;
  return d;
}

// Calls f<2>() or f<3>().
template <class F>
auto by_dimension(int d, F&& f) {
  if (d == 2) return f.template operator()<2>();
  return f.template operator()<3>();
}

// The Python json module's loads(text).
inline py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

}  // namespace ballagg::python
