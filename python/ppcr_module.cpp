// ppcr_module.cpp - the Python module ppcr: register() and read_point_cloud() on numpy arrays.
//
// Clouds come in as (N, 3) arrays of any real dtype and memory layout, copied into the library's
// PointCloud (float64). Options are keyword arguments named after the fields of
// RegistrationOptions and of its ExpertOptions, with their defaults read off a default-constructed
// struct, so they cannot drift from the library's. The library never throws: a Status that is not
// ok becomes ValueError with the library's message. Registration and file reading run with the
// GIL released; the per-iteration callback takes it back for the Python side only.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ppcr/io.hpp"
#include "ppcr/ppcr.hpp"

namespace py = pybind11;

namespace {

using ppcr::ExpertOptions;
using ppcr::RegistrationOptions;

[[noreturn]] void value_error(const std::string& message) { throw py::value_error(message); }
[[noreturn]] void type_error(const std::string& message) { throw py::type_error(message); }

std::string type_name(const py::handle& obj) { return Py_TYPE(obj.ptr())->tp_name; }

// ------------------------------------------------------------------------------------- arrays

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    s += (i > 0 ? ", " : "") + std::to_string(a.shape(i));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// obj (anything numpy.asarray takes) as a C-contiguous float64 array of shape (rows, cols),
// rows < 0 meaning any number of rows. Integer and floating dtypes are converted; anything else
// (strings, objects, booleans, complex) and any other shape is a ValueError naming `name`.
py::array_t<double> as_doubles(const py::handle& obj, const std::string& name, py::ssize_t rows,
                               py::ssize_t cols) {
  const std::string expected = "an array of shape (" +
                               (rows < 0 ? std::string("N") : std::to_string(rows)) + ", " +
                               std::to_string(cols) + ")";
  if (obj.is_none()) value_error(name + ": expected " + expected + ", got None");
  py::array a = py::array::ensure(obj);
  if (!a) value_error(name + ": expected " + expected + " of numbers, got " + type_name(obj));
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    value_error(name + ": expected real numbers, got dtype " + std::string(py::str(a.dtype())));
  }
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || a.shape(1) != cols) {
    value_error(name + ": expected " + expected + ", got shape " + shape_text(a));
  }
  using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
  Doubles d = Doubles::ensure(a);
  if (!d) value_error(name + ": cannot convert dtype " + std::string(py::str(a.dtype())));
  return std::move(d);
}

ppcr::PointCloud to_cloud(const py::handle& obj, const char* name) {
  const py::array_t<double> a = as_doubles(obj, name, -1, 3);
  const auto r = a.unchecked<2>();
  ppcr::PointCloud cloud(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    cloud[static_cast<std::size_t>(i)] = Eigen::Vector3d(r(i, 0), r(i, 1), r(i, 2));
  }
  return cloud;
}

py::array_t<double> to_array(const ppcr::PointCloud& cloud) {
  py::array_t<double> a({static_cast<py::ssize_t>(cloud.size()), py::ssize_t{3}});
  auto w = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int c = 0; c < 3; ++c) w(static_cast<py::ssize_t>(i), c) = cloud[i](c);
  }
  return a;
}

template <int Rows, int Cols>
py::array_t<double> to_array(const Eigen::Matrix<double, Rows, Cols>& m) {
  py::array_t<double> a({py::ssize_t{Rows}, py::ssize_t{Cols}});
  auto w = a.mutable_unchecked<2>();
  for (int r = 0; r < Rows; ++r) {
    for (int c = 0; c < Cols; ++c) w(r, c) = m(r, c);
  }
  return a;
}

// The initial guess: a rigid 4x4 matrix, as ppcr_cli's --initial (ppcr::io::read_transform)
// requires. Non-finite entries are left to the library, which names them.
Eigen::Isometry3d to_transform(const py::handle& obj) {
  const py::array_t<double> a = as_doubles(obj, "initial", 4, 4);
  const auto r = a.unchecked<2>();
  Eigen::Matrix4d M;
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 4; ++c) M(i, c) = r(i, c);
  }
  if (M.allFinite() && !ppcr::se3::is_rigid(M)) {
    value_error(
        "initial: not a rigid transform (a rotation block with R^T R = I and det R = +1, and "
        "the last row 0 0 0 1, within 1e-6)");
  }
  Eigen::Isometry3d T;
  T.matrix() = M;
  return T;
}

// ------------------------------------------------------------------------------------ options

// A field of RegistrationOptions or of its ExpertOptions, by member pointer.
template <class T>
T& at(RegistrationOptions& o, T RegistrationOptions::*m) {
  return o.*m;
}
template <class T>
T& at(RegistrationOptions& o, T ExpertOptions::*m) {
  return o.expert.*m;
}
template <class T>
const T& at(const RegistrationOptions& o, T RegistrationOptions::*m) {
  return o.*m;
}
template <class T>
const T& at(const RegistrationOptions& o, T ExpertOptions::*m) {
  return o.expert.*m;
}

bool is_bool(const py::handle& v) {
  return PyBool_Check(v.ptr()) || type_name(v) == std::string("numpy.bool_");
}

// Python values into fields: numbers (Python's or numpy's; not bool, not str), integers (no
// float, even a whole one, as a C++ int would not take it silently either), and booleans.
double to_field(const py::handle& v, const std::string& name, double*) {
  if (is_bool(v) || !PyNumber_Check(v.ptr())) {
    type_error(name + ": expected a number, got " + type_name(v));
  }
  const double d = PyFloat_AsDouble(v.ptr());
  if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return d;
}

int to_field(const py::handle& v, const std::string& name, int*) {
  if (is_bool(v) || !PyIndex_Check(v.ptr())) {
    type_error(name + ": expected an integer, got " + type_name(v));
  }
  const long long i =
      PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr())).ptr());
  if (i == -1 && PyErr_Occurred()) {
    PyErr_Clear();
    value_error(name + ": " + std::string(py::str(v)) + " does not fit in a C int");
  }
  if (i < INT32_MIN || i > INT32_MAX) {
    value_error(name + ": " + std::to_string(i) + " does not fit in a C int");
  }
  return static_cast<int>(i);
}

bool to_field(const py::handle& v, const std::string& name, bool*) {
  if (!is_bool(v)) type_error(name + ": expected True or False, got " + type_name(v));
  return PyObject_IsTrue(v.ptr()) == 1;
}

struct Option {
  std::string name;
  std::string doc;
  std::function<void(RegistrationOptions*, const py::handle&)> set;  // raises naming the option
  std::function<py::object(const RegistrationOptions&)> get;
};

template <class Member>
Option value(const char* name, Member member, const std::string& doc) {
  return {name, doc,
          [name, member](RegistrationOptions* o, const py::handle& v) {
            auto& field = at(*o, member);
            field = to_field(v, name, &field);
          },
          [member](const RegistrationOptions& o) { return py::cast(at(o, member)); }};
}

// An enum field spelt as one of a few words.
template <class Member, class Enum>
Option word(const char* name, Member member, std::vector<std::pair<std::string, Enum>> words,
            const char* doc) {
  std::string choices;
  for (std::size_t i = 0; i < words.size(); ++i) {
    choices += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + ("'" + words[i].first + "'");
  }
  return {name, doc,
          [name, member, words, choices](RegistrationOptions* o, const py::handle& v) {
            if (!py::isinstance<py::str>(v)) {
              type_error(std::string(name) + ": expected " + choices + ", got " + type_name(v));
            }
            const std::string text = py::str(v);
            for (const auto& [w, e] : words) {
              if (w == text) return void(at(*o, member) = e);
            }
            value_error(std::string(name) + ": expected " + choices + ", got '" + text + "'");
          },
          [member, words](const RegistrationOptions& o) {
            for (const auto& [w, e] : words) {
              if (at(o, member) == e) return py::object(py::str(w));
            }
            return py::object(py::none());
          }};
}

const std::vector<std::pair<std::string, ppcr::Criterion>>& criterion_words() {
  static const std::vector<std::pair<std::string, ppcr::Criterion>> words = {
      {"cost_drop", ppcr::kCriterionCostDrop},
      {"mse_prev", ppcr::kCriterionMsePrev},
      {"successful_steps", ppcr::kCriterionSuccessfulSteps},
      {"fixed", ppcr::kCriterionFixed}};
  return words;
}

// criteria: a name or a sequence of names, OR-ed.
Option criteria_option() {
  const char* kName = "criteria";
  const std::string choices = "'cost_drop', 'mse_prev', 'successful_steps' or 'fixed'";
  return {kName,
          "termination criteria, a name or a list of names among 'cost_drop' (the paper's eq. "
          "7), 'mse_prev' (eq. 5-6), 'successful_steps' and 'fixed'; the loop stops when any "
          "fires",
          [kName, choices](RegistrationOptions* o, const py::handle& v) {
            std::vector<py::handle> items;
            py::list held;  // keeps a sequence's items alive
            if (py::isinstance<py::str>(v)) {
              items.push_back(v);
            } else if (py::isinstance<py::sequence>(v)) {
              held = py::list(py::reinterpret_borrow<py::object>(v));
              for (const py::handle& item : held) items.push_back(item);
            } else {
              type_error(std::string(kName) + ": expected a name or a list of names, got " +
                         type_name(v));
            }
            std::uint32_t bits = 0;
            for (const py::handle& item : items) {
              bool known = false;
              if (py::isinstance<py::str>(item)) {
                const std::string text = py::str(item);
                for (const auto& [w, bit] : criterion_words()) {
                  if (w == text) bits |= bit, known = true;
                }
              }
              if (!known) {
                value_error(std::string(kName) + ": expected " + choices + ", got " +
                            std::string(py::repr(item)));
              }
            }
            o->criteria = bits;  // none: only max_iterations stops the loop
          },
          [](const RegistrationOptions& o) {
            py::list names;
            for (const auto& [w, bit] : criterion_words()) {
              if ((o.criteria & bit) != 0u) names.append(w);
            }
            return py::object(names);
          }};
}

// Every field of RegistrationOptions (on_iteration apart: register()'s own argument) and of
// ExpertOptions, in the header's order, with its unit and range (include/ppcr/options.hpp).
const std::vector<Option>& options_table() {
  using E = ExpertOptions;
  using R = RegistrationOptions;
  static const std::vector<Option> table = {
      value("radius", &R::radius,
            "association radius, cloud units (> 0): target points farther than this are "
            "ignored; 0: automatic, 8 x the filtered target's median point spacing"),
      value("max_neighbours", &R::max_neighbours,
            "target points associated per source point, in [1, 1024]"),
      word("error_model", &R::error_model,
           std::vector<std::pair<std::string, ppcr::ErrorModel>>{
               {"plane", ppcr::ErrorModel::kPlane}, {"point", ppcr::ErrorModel::kPoint}},
           "'plane' (the error along the surfaces' normals) or 'point' (the paper's)"),
      value("dof", &R::dof, "Student-t degrees of freedom (> 0)"),
      value("source_voxel", &R::source_voxel,
            "voxel-grid leaf for the source, cloud units (>= 0; 0 = no filter; "
            "ppcr.AUTOMATIC_VOXEL: the leaf leaving about " +
                std::to_string(R::kAutomaticVoxelPoints) + " points)"),
      value("target_voxel", &R::target_voxel,
            "voxel-grid leaf for the target, cloud units (>= 0; 0 = no filter; "
            "ppcr.AUTOMATIC_VOXEL: the leaf leaving about " +
                std::to_string(R::kAutomaticVoxelPoints) + " points)"),
      criteria_option(),
      value("max_iterations", &R::max_iterations,
            "hard cap on outer iterations, whatever the criteria (>= 1)"),
      value("num_threads", &R::num_threads,
            "threads, in [1, 1024]; the result does not depend on it"),
      value("record_history", &R::record_history, "keep the per-iteration trace (Result.history)"),
      // ExpertOptions: the method's research and speed parameters.
      word("weight_model", &E::weight_model,
           std::vector<std::pair<std::string, ppcr::WeightModel>>{
               {"student_t", ppcr::WeightModel::kStudentT},
               {"gaussian", ppcr::WeightModel::kGaussian}},
           "expert: E-step posterior, 'student_t' (paper eq. 3-4) or 'gaussian' (eq. 2)"),
      word("scale_mode", &E::scale_mode,
           std::vector<std::pair<std::string, ppcr::ScaleMode>>{{"em", ppcr::ScaleMode::kEM},
                                                                {"raw", ppcr::ScaleMode::kRaw},
                                                                {"fixed", ppcr::ScaleMode::kFixed}},
           "expert: E-step scale s, 'em' (coarse-to-fine), 'raw' (1 cloud unit, the paper's) or "
           "'fixed' (= scale)"),
      value("scale", &E::scale,
            "expert: 'fixed': s (> 0); 'em': the coarse s (0 = radius / 2); cloud units"),
      value("em_coarse_drop", &E::em_coarse_drop,
            "expert: 'em' coarse phase: a relative cost drop below this is settled (>= 0)"),
      value("em_coarse_patience", &E::em_coarse_patience,
            "expert: 'em' coarse phase: settled iterations that end it (>= 0)"),
      value("em_min_shrink", &E::em_min_shrink,
            "expert: 'em' fine phase: s^2 shrinks by at most this factor per iteration, (0, 1]"),
      value("em_min_scale", &E::em_min_scale,
            "expert: 'em' fine phase: floor on s, cloud units (>= 0; 0 = none)"),
      value("normal_neighbours", &E::normal_neighbours,
            "expert: points per PCA normal fit, in [5, 64]"),
      value("plane_epsilon", &E::plane_epsilon,
            "expert: in-plane weight epsilon of the plane error, (0, 1]"),
      value("source_normals", &E::source_normals,
            "expert: pairs use the mean of both clouds' normals (GICP-like)"),
      value("reject_boundary", &E::reject_boundary,
            "expert: plane model, 'em': after the coarse phase, leave out source points whose "
            "nearest target point lies on the target's boundary (unless over half would go)"),
      value("noise_floor", &E::noise_floor,
            "expert: 'em': floor s at this multiple of the target's surface noise (>= 0; 0 = "
            "none)"),
      value("fixed_iterations", &E::fixed_iterations,
            "expert: criterion 'fixed' stops at this iteration (>= 1)"),
      value("cost_drop_threshold", &E::cost_drop_threshold,
            "expert: criterion 'cost_drop': a relative drop below this is low (paper: 0.01)"),
      value("cost_drop_patience", &E::cost_drop_patience,
            "expert: criterion 'cost_drop': low iterations tolerated (paper: 10)"),
      value("cost_drop_max_motion", &E::cost_drop_max_motion,
            "expert: criterion 'cost_drop': a low iteration must also move the source by less "
            "than this fraction of the radius, RMS (0 = the paper's rule)"),
      value("mse_ratio_threshold", &E::mse_ratio_threshold,
            "expert: criterion 'mse_prev': low when MSE_t < MSE_{t-1} / this (> 0)"),
      value("mse_patience", &E::mse_patience,
            "expert: criterion 'mse_prev': low iterations tolerated (>= 0)"),
      value("successful_steps_threshold", &E::successful_steps_threshold,
            "expert: criterion 'successful_steps': low when LM accepts at most this many steps"),
      value("successful_steps_patience", &E::successful_steps_patience,
            "expert: criterion 'successful_steps': low iterations tolerated"),
      value("acceleration_memory", &E::acceleration_memory,
            "expert: 'em' coarse phase: Anderson acceleration of the pose with this memory m "
            "(from the last m + 1 iterations), [0, 8] (0 = the paper's plain loop)"),
      value("lm_max_iterations", &E::lm_max_iterations,
            "expert: Levenberg-Marquardt steps per solve (>= 1)"),
      value("lm_function_tolerance", &E::lm_function_tolerance,
            "expert: a solve ends when an accepted step lowers the cost by less than this "
            "fraction (>= 0)"),
      value("lm_fine_function_tolerance", &E::lm_fine_function_tolerance,
            "expert: the same in the 'em' fine phase (>= 0; -1 = automatic)"),
      value("neighbour_cache", &E::neighbour_cache,
            "expert: extra candidates cached per source point (0 = none; same result)"),
      value("coarse_stride", &E::coarse_stride,
            "expert: 'em': register every n-th source point while the scale settles (the "
            "coarse phase and its halving), in [1, 64] (-1 = automatic: 2 with the plane model, "
            "1 with the point model)"),
  };
  return table;
}

py::dict default_options() {
  const RegistrationOptions defaults;
  py::dict d;
  for (const Option& option : options_table()) d[py::str(option.name)] = option.get(defaults);
  return d;
}

RegistrationOptions to_options(const py::kwargs& kwargs) {
  RegistrationOptions options;
  for (const auto& [key, v] : kwargs) {
    const std::string name = py::str(key);
    bool known = false;
    for (const Option& option : options_table()) {
      if (option.name == name) option.set(&options, v), known = true;
    }
    if (!known) {
      type_error("register() got an unexpected keyword argument '" + name +
                 "' (ppcr.default_options() lists the options)");
    }
  }
  return options;
}

// ------------------------------------------------------------------------------------- result

struct Result {
  py::array_t<double> transformation;  // 4x4, maps source into target
  std::string status = "ok";           // "ok", or "no_correspondences" (see status_message)
  std::string status_message;
  bool converged = false;
  std::string stop_reason;
  int iterations = 0;
  int lm_iterations = 0;
  int lm_successful_steps = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double scale = 0.0;
  std::size_t source_points = 0;
  std::size_t target_points = 0;
  std::size_t matched_source_points = 0;
  std::size_t correspondences = 0;
  std::size_t source_non_finite = 0;
  std::size_t target_non_finite = 0;
  std::size_t source_duplicates = 0;
  std::size_t target_duplicates = 0;
  double target_surface_noise = 0.0;
  double target_spacing = 0.0;
  double radius = 0.0;
  double source_voxel = 0.0, target_voxel = 0.0;
  py::array_t<double> information;  // 6x6
  py::array_t<double> covariance;   // 6x6
  int degenerate_directions = -1;
  double fitness = 0.0;
  double inlier_rmse = 0.0;
  double overlap = 0.0;
  double close_fraction = 0.0;
  std::string quality;
  std::string quality_reason;
  double quality_ms = 0.0;
  double time_ms = 0.0;  // wall time of the registration call (as ppcr_cli's)
  py::dict history;      // the trace: one array per IterationRecord field, one row per iteration
};

py::dict record_dict(const ppcr::IterationRecord& h) {
  py::dict d;
  d["iteration"] = h.iteration;
  d["coarse"] = h.coarse;
  d["successful_steps"] = h.successful_steps;
  d["unsuccessful_steps"] = h.unsuccessful_steps;
  d["initial_cost"] = h.initial_cost;
  d["final_cost"] = h.final_cost;
  d["cost_drop"] = h.cost_drop;
  d["mse_prev"] = h.mse_prev;
  d["scale"] = h.scale;
  d["correspondences"] = h.correspondences;
  d["matched_source_points"] = h.matched_source_points;
  d["transformation"] = to_array(Eigen::Matrix4d(h.T_target_source.matrix()));
  d["time_ms"] = h.time_ms;
  return d;
}

template <class T, class Field>
py::array_t<T> column(const std::vector<ppcr::IterationRecord>& history, Field field) {
  py::array_t<T> a(static_cast<py::ssize_t>(history.size()));
  auto w = a.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < history.size(); ++i) {
    w(static_cast<py::ssize_t>(i)) = static_cast<T>(field(history[i]));
  }
  return a;
}

py::dict history_dict(const std::vector<ppcr::IterationRecord>& history) {
  using H = ppcr::IterationRecord;
  py::dict d;
  d["iteration"] = column<std::int64_t>(history, [](const H& h) { return h.iteration; });
  d["coarse"] = column<bool>(history, [](const H& h) { return h.coarse; });
  d["successful_steps"] =
      column<std::int64_t>(history, [](const H& h) { return h.successful_steps; });
  d["unsuccessful_steps"] =
      column<std::int64_t>(history, [](const H& h) { return h.unsuccessful_steps; });
  d["initial_cost"] = column<double>(history, [](const H& h) { return h.initial_cost; });
  d["final_cost"] = column<double>(history, [](const H& h) { return h.final_cost; });
  d["cost_drop"] = column<double>(history, [](const H& h) { return h.cost_drop; });
  d["mse_prev"] = column<double>(history, [](const H& h) { return h.mse_prev; });
  d["scale"] = column<double>(history, [](const H& h) { return h.scale; });
  d["correspondences"] =
      column<std::int64_t>(history, [](const H& h) { return h.correspondences; });
  d["matched_source_points"] =
      column<std::int64_t>(history, [](const H& h) { return h.matched_source_points; });
  py::array_t<double> poses(
      {static_cast<py::ssize_t>(history.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto w = poses.mutable_unchecked<3>();
  for (std::size_t i = 0; i < history.size(); ++i) {
    const Eigen::Matrix4d& M = history[i].T_target_source.matrix();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) w(static_cast<py::ssize_t>(i), r, c) = M(r, c);
    }
  }
  d["transformation"] = poses;
  d["time_ms"] = column<double>(history, [](const H& h) { return h.time_ms; });
  return d;
}

// A registration that ran but found no target point near any source point is a result (status
// "no_correspondences", verdict failed, fitness 0), as Open3D returns one with fitness 0, so a
// loop can go on; a refused input is a ValueError.
bool refused(const ppcr::Status& status) {
  return !status.ok() && status.code() != ppcr::StatusCode::kNoCorrespondences;
}

Result to_result(const ppcr::RegistrationResult& r, double time_ms) {
  Result out;
  out.transformation = to_array(Eigen::Matrix4d(r.T_target_source.matrix()));
  out.status = ppcr::to_string(r.status.code());
  out.status_message = r.status.message();
  out.converged = r.converged();
  out.stop_reason = ppcr::to_string(r.stop_reason);
  out.iterations = r.iterations;
  out.lm_iterations = r.lm_iterations;
  out.lm_successful_steps = r.lm_successful_steps;
  out.initial_cost = r.initial_cost;
  out.final_cost = r.final_cost;
  out.scale = r.scale;
  out.source_points = r.source_points;
  out.target_points = r.target_points;
  out.matched_source_points = r.matched_source_points;
  out.correspondences = r.correspondences;
  out.source_non_finite = r.source_non_finite;
  out.target_non_finite = r.target_non_finite;
  out.source_duplicates = r.source_duplicates;
  out.target_duplicates = r.target_duplicates;
  out.target_surface_noise = r.target_surface_noise;
  out.target_spacing = r.target_spacing;
  out.radius = r.radius;
  out.source_voxel = r.source_voxel;
  out.target_voxel = r.target_voxel;
  out.information = to_array(r.information);
  out.covariance = to_array(r.covariance);
  out.degenerate_directions = r.degenerate_directions;
  out.fitness = r.fitness;
  out.inlier_rmse = r.inlier_rmse;
  out.overlap = r.overlap;
  out.close_fraction = r.close_fraction;
  out.quality = ppcr::to_string(r.quality);
  out.quality_reason = r.quality_reason;
  out.quality_ms = r.quality_ms;
  out.time_ms = time_ms;
  out.history = history_dict(r.history);
  return out;
}

// ----------------------------------------------------------------------------------- register

// What the per-iteration callback hands back to register(): the Python error that stopped the
// registration (the user's callback raised, or Ctrl-C). The callback holds a plain handle to the
// user's function, never a reference count: the library copies and destroys options with the GIL
// released.
struct CallbackState {
  py::handle function;  // None: no user callback
  std::unique_ptr<py::error_already_set> error;
  std::string cpp_error;
};

bool on_iteration(CallbackState* state, const ppcr::IterationRecord& record) {
  py::gil_scoped_acquire gil;
  try {
    // Ctrl-C (a signal handled by Python's main thread) cancels the registration.
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (state->function.is_none()) return true;
    const py::object answer = state->function(record_dict(record));
    // None (no return statement) continues; a false value stops.
    if (answer.is_none()) return true;
    const int truth = PyObject_IsTrue(answer.ptr());
    if (truth < 0) throw py::error_already_set();
    return truth == 1;
  } catch (py::error_already_set& e) {
    state->error = std::make_unique<py::error_already_set>(std::move(e));
  } catch (const std::exception& e) {
    state->cpp_error = e.what();
  }
  return false;
}

Result register_clouds(const py::handle& source, const py::handle& target,
                       const py::handle& initial, const py::handle& callback,
                       const py::kwargs& kwargs) {
  RegistrationOptions options = to_options(kwargs);
  ppcr::PointCloud source_cloud = to_cloud(source, "source");
  ppcr::PointCloud target_cloud = to_cloud(target, "target");
  const Eigen::Isometry3d T_initial =
      initial.is_none() ? Eigen::Isometry3d::Identity() : to_transform(initial);
  if (!callback.is_none() && !PyCallable_Check(callback.ptr())) {
    type_error("on_iteration: expected a callable or None, got " + type_name(callback));
  }
  CallbackState state;
  state.function = callback;
  options.on_iteration = [&state](const ppcr::IterationRecord& record) {
    return on_iteration(&state, record);
  };

  ppcr::RegistrationResult r;
  double time_ms = 0.0;
  {
    py::gil_scoped_release release;
    const auto start = std::chrono::steady_clock::now();
    // The converted clouds are freed once the registration holds its prepared copies (a
    // refused target makes align() refused with its status).
    ppcr::Registration registration(options);
    (void)registration.set_target(target_cloud);
    ppcr::PointCloud().swap(target_cloud);
    r = registration.align(std::move(source_cloud), T_initial);
    time_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  if (state.error) throw *state.error;
  if (!state.cpp_error.empty()) throw std::runtime_error("on_iteration: " + state.cpp_error);
  if (refused(r.status)) value_error(r.status.message());
  return to_result(r, time_ms);
}

// A str, bytes or os.PathLike path as the C++ string the readers take.
std::string path_text(const py::handle& path) {
  const py::object fs_path = py::module_::import("os").attr("fspath")(path);
  return py::isinstance<py::bytes>(fs_path) ? std::string(py::bytes(fs_path))
                                            : std::string(py::str(fs_path));
}

// A failed file Status as Python raises it: OSError's family for a file that cannot be read or
// written (as open() would), ValueError for its content or for a refused value.
[[noreturn]] void raise_file_error(const ppcr::Status& s, const std::string& path) {
  if (s.code() == ppcr::StatusCode::kIoError) {
    std::error_code ec;
    PyObject* type = PyExc_OSError;
    if (s.message().find("Permission denied") != std::string::npos) {
      type = PyExc_PermissionError;
    } else if (std::filesystem::is_directory(path, ec)) {
      type = PyExc_IsADirectoryError;
    } else if (!std::filesystem::exists(path, ec)) {
      type = PyExc_FileNotFoundError;
    }
    PyErr_SetString(type, s.message().c_str());
    throw py::error_already_set();
  }
  value_error(s.message());
}

// depth_intrinsics (fx, fy, cx, cy) and depth_scale, as ppcr_cli's --depth-intrinsics and
// --depth-scale: ppcr::io::DepthCamera's defaults (TUM's) where None.
ppcr::io::DepthCamera depth_camera(const py::object& intrinsics, const py::object& scale) {
  ppcr::io::DepthCamera camera;
  if (!intrinsics.is_none()) {
    std::vector<double> v;
    if (!py::isinstance<py::sequence>(intrinsics) || py::isinstance<py::str>(intrinsics)) {
      throw py::type_error("depth_intrinsics must be a sequence of 4 numbers (fx, fy, cx, cy)");
    }
    for (const py::handle item : intrinsics) {
      try {
        v.push_back(item.cast<double>());
      } catch (const py::cast_error&) {
        throw py::type_error("depth_intrinsics must be a sequence of 4 numbers (fx, fy, cx, cy)");
      }
    }
    if (v.size() != 4) {
      value_error("depth_intrinsics must hold 4 numbers (fx, fy, cx, cy); got " +
                  std::to_string(v.size()));
    }
    camera.fx = v[0], camera.fy = v[1], camera.cx = v[2], camera.cy = v[3];
  }
  if (!scale.is_none()) camera.depth_scale = to_field(scale, "depth_scale", &camera.depth_scale);
  return camera;
}

py::array_t<double> read_point_cloud(const py::handle& path, const py::object& depth_intrinsics,
                                     const py::object& depth_scale) {
  const std::string text = path_text(path);
  const ppcr::io::DepthCamera camera = depth_camera(depth_intrinsics, depth_scale);
  ppcr::PointCloud cloud;
  ppcr::Status s;
  {
    py::gil_scoped_release release;
    s = ppcr::io::read_cloud(text, camera, &cloud);
  }
  if (!s.ok()) raise_file_error(s, text);
  return to_array(cloud);
}

void write_point_cloud(const py::handle& path, const py::handle& points) {
  const std::string text = path_text(path);
  const ppcr::PointCloud cloud = to_cloud(points, "points");
  ppcr::Status s;
  {
    py::gil_scoped_release release;
    s = ppcr::io::write_cloud(text, cloud);
  }
  if (!s.ok()) raise_file_error(s, text);
}

py::array_t<double> voxel_downsample(const py::handle& points, double leaf) {
  const ppcr::PointCloud cloud = to_cloud(points, "points");
  ppcr::PointCloud out;
  ppcr::Status s;
  {
    py::gil_scoped_release release;
    s = ppcr::voxel_downsample(cloud, leaf, &out);
  }
  if (!s.ok()) value_error(s.message());
  return to_array(out);
}

py::dict evaluate(const py::handle& source, const py::handle& T_est, const py::handle& T_gt) {
  const ppcr::PointCloud cloud = to_cloud(source, "source");
  const ppcr::PoseErrors e = ppcr::evaluate(cloud, to_transform(T_est), to_transform(T_gt));
  py::dict d;
  d["rotation_error_deg"] = e.rotation_error_deg;
  d["translation_error"] = e.translation_error;
  d["benchmark_error"] = e.benchmark_error;
  d["mse"] = e.mse;
  return d;
}

// ppcr.Registration: one target, prepared once, for many sources (a loop of scans). The same
// options and results as register(); set_target_to_source() makes the last source the target.
class PyRegistration {
 public:
  explicit PyRegistration(const py::kwargs& kwargs) : registration_(to_options(kwargs)) {}

  void set_target(const py::handle& target) {
    const ppcr::PointCloud cloud = to_cloud(target, "target");
    ppcr::Status s;
    {
      py::gil_scoped_release release;
      s = registration_.set_target(cloud);
    }
    if (!s.ok()) value_error(s.message());
  }

  Result align(const py::handle& source, const py::handle& initial) {
    ppcr::PointCloud cloud = to_cloud(source, "source");
    const Eigen::Isometry3d T_initial =
        initial.is_none() ? Eigen::Isometry3d::Identity() : to_transform(initial);
    ppcr::RegistrationResult r;
    double time_ms = 0.0;
    {
      py::gil_scoped_release release;
      const auto start = std::chrono::steady_clock::now();
      r = registration_.align(std::move(cloud), T_initial);
      time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count();
    }
    if (refused(r.status)) value_error(r.status.message());
    return to_result(r, time_ms);
  }

  void set_target_to_source() {
    ppcr::Status s;
    {
      py::gil_scoped_release release;
      s = registration_.set_target_to_source();
    }
    if (!s.ok()) value_error(s.message());
  }

 private:
  ppcr::Registration registration_;
};

std::string register_doc() {
  std::string doc =
      "register(source, target, *, initial=None, on_iteration=None, **options) -> Result\n\n"
      "Registers source onto target: finds the rigid transform mapping source points into the\n"
      "target's frame, starting from `initial` (a rigid 4x4 matrix; None: identity).\n"
      "source, target: (N, 3) arrays of real numbers (any dtype and layout; copied as float64).\n"
      "Non-finite points are dropped and counted (Result.source_non_finite...).\n"
      "on_iteration: called after each outer iteration with a dict (the fields of\n"
      "Result.history, one iteration's values); return False to stop (stop_reason "
      "'cancelled').\n"
      "Raises ValueError with the library's message for refused input; a registration that\n"
      "finds no overlap returns a Result with status 'no_correspondences' and quality\n"
      "'failed'.\n\n"
      "Options (keyword only; the fields of ppcr::RegistrationOptions and ExpertOptions, with\n"
      "their defaults; lengths in cloud units):\n";
  const RegistrationOptions defaults;
  for (const Option& option : options_table()) {
    doc += "  " + option.name + "=" + std::string(py::repr(option.get(defaults))) + ": " +
           option.doc + "\n";
  }
  return doc;
}

}  // namespace

PYBIND11_MODULE(ppcr, m) {
  // The docstrings start with their own signature lines (pybind11's would show py::handle).
  py::options docstring_options;
  docstring_options.disable_function_signatures();
  m.doc() =
      "ppcr: Probabilistic Point Clouds Registration with automatic termination.\n"
      "register(source, target, radius=..., ...) aligns two (N, 3) numpy clouds;\n"
      "read_point_cloud(path) reads PLY, PCD, XYZ/CSV/PTS and KITTI .bin files.";
  m.attr("__version__") = PPCR_VERSION_STRING;
  m.attr("AUTOMATIC_VOXEL") = ppcr::RegistrationOptions::kAutomaticVoxel;

  py::class_<Result>(m, "Result", "What register() returns (ppcr::RegistrationResult).")
      .def_readonly("transformation", &Result::transformation,
                    "4x4 float64 array: maps source points into the target's frame")
      .def_readonly("converged", &Result::converged,
                    "True when a termination criterion stopped the loop (not the cap)")
      .def_readonly("status", &Result::status,
                    "'ok', or 'no_correspondences' when no source point had a target point "
                    "within the radius (the pose is the initial guess; quality 'failed')")
      .def_readonly("status_message", &Result::status_message,
                    "why the status is not 'ok' (the library's message), else ''")
      .def_readonly("stop_reason", &Result::stop_reason,
                    "why the loop stopped: 'cost_drop', 'max_iterations', 'cancelled'...")
      .def_readonly("iterations", &Result::iterations, "outer iterations run")
      .def_readonly("lm_iterations", &Result::lm_iterations, "LM steps, accepted and rejected")
      .def_readonly("lm_successful_steps", &Result::lm_successful_steps, "accepted LM steps")
      .def_readonly("initial_cost", &Result::initial_cost, "first inner problem's initial cost")
      .def_readonly("final_cost", &Result::final_cost, "last inner problem's final cost")
      .def_readonly("scale", &Result::scale, "final E-step scale, cloud units")
      .def_readonly("source_points", &Result::source_points, "source points registered")
      .def_readonly("target_points", &Result::target_points, "target points used")
      .def_readonly("matched_source_points", &Result::matched_source_points,
                    "source points with a neighbour in the last iteration")
      .def_readonly("correspondences", &Result::correspondences,
                    "associated pairs in the last iteration")
      .def_readonly("source_non_finite", &Result::source_non_finite,
                    "source points dropped as non-finite")
      .def_readonly("target_non_finite", &Result::target_non_finite,
                    "target points dropped as non-finite")
      .def_readonly("source_duplicates", &Result::source_duplicates,
                    "copies of a source point (equal in the solver's frame), registered once")
      .def_readonly("target_duplicates", &Result::target_duplicates,
                    "copies of a target point (equal in the solver's frame), used once")
      .def_readonly("target_surface_noise", &Result::target_surface_noise,
                    "plane model: the target's surface noise, cloud units")
      .def_readonly("target_spacing", &Result::target_spacing,
                    "the target's median point spacing, cloud units")
      .def_readonly("radius", &Result::radius,
                    "the association radius used, cloud units (the option, or the automatic one)")
      .def_readonly("source_voxel", &Result::source_voxel,
                    "the source's voxel leaf used, cloud units (0: not filtered)")
      .def_readonly("target_voxel", &Result::target_voxel,
                    "the target's voxel leaf used, cloud units (0: not filtered)")
      .def_readonly("information", &Result::information,
                    "6x6 Gauss-Newton information at the final pose (about the target's median "
                    "point; not a covariance's inverse)")
      .def_readonly("covariance", &Result::covariance,
                    "6x6 covariance of the pose: of the twist (rotation, translation) applied on "
                    "the left of T_target_source about the target frame's origin; radians and "
                    "cloud units")
      .def_readonly("degenerate_directions", &Result::degenerate_directions,
                    "motions the target's surfaces leave unconstrained (-1: not assessed)")
      .def_readonly("fitness", &Result::fitness,
                    "fraction of source points with a target point within the radius")
      .def_readonly("inlier_rmse", &Result::inlier_rmse,
                    "RMS distance of those points to their nearest target point")
      .def_readonly("overlap", &Result::overlap, "the matched fraction both ways")
      .def_readonly("close_fraction", &Result::close_fraction,
                    "of the source points near the target, the fraction on its surface (within 2 "
                    "target point spacings of its tangent plane and the target's median normal-fit "
                    "reach of its nearest point, with the plane model)")
      .def_readonly("quality", &Result::quality,
                    "the verdict: 'good', 'weak' (check it) or 'failed' (do not use the pose)")
      .def_readonly("quality_reason", &Result::quality_reason,
                    "why the verdict is not 'good' (empty when it is)")
      .def_readonly("quality_ms", &Result::quality_ms, "time of fitness, inlier_rmse, overlap")
      .def_readonly("time_ms", &Result::time_ms, "wall time of the registration call, ms")
      .def_readonly("history", &Result::history,
                    "the per-iteration trace: a dict of arrays, one row per outer iteration "
                    "(empty with record_history=False)")
      .def("__repr__", [](const Result& r) {
        // As ppcr_cli's summary line.
        char text[256];
        std::snprintf(text, sizeof(text),
                      "<ppcr.Result %s after %d iterations (%s), quality %s, fitness %.4f, "
                      "inlier_rmse %.6g, overlap %.4f, %.1f ms>",
                      r.converged ? "converged" : "stopped", r.iterations, r.stop_reason.c_str(),
                      r.quality.c_str(), r.fitness, r.inlier_rmse, r.overlap, r.time_ms);
        return std::string(text);
      });

  m.def("register", &register_clouds, py::arg("source"), py::arg("target"), py::kw_only(),
        py::arg("initial") = py::none(), py::arg("on_iteration") = py::none(),
        register_doc().c_str());
  m.def("read_point_cloud", &read_point_cloud, py::arg("path"), py::kw_only(),
        py::arg("depth_intrinsics") = py::none(), py::arg("depth_scale") = py::none(),
        "read_point_cloud(path, *, depth_intrinsics=None, depth_scale=None) -> (N, 3) float64\n\n"
        "Reads a PLY, PCD, XYZ/CSV/PTS or KITTI .bin file, or a depth image (16-bit PNG), with\n"
        "ppcr's readers (format by extension, else by content). A depth image's pixels with\n"
        "depth are back-projected through depth_intrinsics (fx, fy, cx, cy; pixels) and\n"
        "depth_scale (stored value per metre); None: TUM's defaults (525, 525, 319.5, 239.5;\n"
        "5000). Points with a non-finite coordinate are dropped. A file that cannot be read\n"
        "raises OSError (FileNotFoundError, IsADirectoryError, PermissionError...), malformed\n"
        "content or no finite point ValueError, each with the reader's message (it names the\n"
        "file and the line or byte).");
  m.def("write_point_cloud", &write_point_cloud, py::arg("path"), py::arg("points"),
        "write_point_cloud(path, points)\n\n"
        "Writes an (N, 3) array with ppcr's writers, the format by extension (.ply and .pcd\n"
        "binary double, .xyz/.txt/.csv/.pts text with 17 digits: exact round trips; .bin KITTI\n"
        "float32). OSError when the file cannot be written, ValueError for the points or an\n"
        "unknown extension.");
  m.def("voxel_downsample", &voxel_downsample, py::arg("points"), py::arg("leaf"),
        "voxel_downsample(points, leaf) -> (M, 3) float64 array\n\n"
        "One centroid per occupied voxel of edge `leaf` (cloud units), as register()'s\n"
        "source_voxel and target_voxel filter.");
  m.def("evaluate", &evaluate, py::arg("source"), py::arg("T_est"), py::arg("T_gt"),
        "evaluate(source, T_est, T_gt) -> dict\n\n"
        "Errors of an estimated pose against a known one, on the registered source cloud:\n"
        "rotation_error_deg, translation_error (cloud units), benchmark_error, mse.");
  py::class_<PyRegistration>(m, "Registration",
                             "Registration(**options): one target prepared once, many sources "
                             "aligned onto it.\n"
                             "The options and the Result are register()'s. The GIL is released "
                             "while it works.")
      .def(py::init<const py::kwargs&>())
      .def("set_target", &PyRegistration::set_target, py::arg("target"),
           "Filters, indexes and fits the normals of the target, once.")
      .def("align", &PyRegistration::align, py::arg("source"), py::kw_only(),
           py::arg("initial") = py::none(),
           "align(source, *, initial=None) -> Result: source onto the target set last.")
      .def("set_target_to_source", &PyRegistration::set_target_to_source,
           "Makes the last aligned source the target, without preparing it again (scan to "
           "scan).");
  m.def("default_options", &default_options,
        "The options of register() with their defaults (those of ppcr::RegistrationOptions).");
}
