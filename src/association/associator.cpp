// associator.cpp - see associator.hpp.
#include "association/associator.hpp"

#include "common/parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

void Associator::set_target(const KdTree* tree, const PointCloud* target,
                            const std::uint8_t* boundary) {
  tree_ = tree;
  target_ = target;
  boundary_ = boundary;
}

void Associator::prepare(const Settings& settings, const PointCloud& source,
                         const std::vector<Eigen::Vector3d>* source_normals) {
  settings_ = settings;
  source_ = &source;
  source_normals_ = source_normals;
  const std::size_t n = source.size();
  const int k = settings.k;
  const int capacity = k + settings.cache_extra;
  use_cache_ = settings.cache_extra > 0 && capacity <= NeighbourCache::kMaxCapacity;
  const std::size_t stride = settings.coarse_stride;
  use_coarse_ = stride > 1;
  coarse_associated_ = false;
  // Sized for every point first, so that the coarse level's rows grow back without allocating.
  table_.resize(n, k);
  // Rows are left out only beyond a target's boundary: room for every row, only when it has one.
  if (boundary_ != nullptr) table_.left_out.reserve(n);
  if (!use_coarse_) {
    // Also forgets the previous source's lists.
    if (use_cache_) cache_.resize(n, capacity, settings.parallel);
    return;
  }
  // Room for every point, as the table's, but its rows reset once, for the coarse level (below).
  if (use_cache_) cache_.reserve(n, capacity);
  const std::size_t n_coarse = (n + stride - 1) / stride;
  // Sized without being written (Eigen's vectors are not zeroed), then copied on the threads:
  // their pages' first touch is a page fault (buffer.hpp).
  coarse_points_.resize(n_coarse);
  if (source_normals_ != nullptr) coarse_normals_.resize(n_coarse);
  constexpr std::size_t kBlock = 4096;
  parallel_for_blocks(settings.parallel, n_coarse, kBlock,
                      [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
                        for (std::size_t i = begin; i < end; ++i) {
                          coarse_points_[i] = source[i * stride];
                          if (source_normals_ != nullptr) {
                            coarse_normals_[i] = (*source_normals_)[i * stride];
                          }
                        }
                      });
  table_.resize(n_coarse, k);
  if (use_cache_) cache_.resize(n_coarse, capacity, settings.parallel);
}

void Associator::find(bool coarse, const Eigen::Isometry3d& T, bool leave_out_boundary) {
  coarse = coarse && use_coarse_;
  table_.any_left_out = false;  // before the association's own count of pairs
  associate(coarse, T);
  if (coarse && table_.pairs == 0) associate(false, T);
  // Once every point is associated the coarse level is gone: its rows were spread over every
  // point, whose lists the cache now holds.
  if (!coarse_associated_) use_coarse_ = false;
  if (leave_out_boundary && boundary_ != nullptr) leave_out_boundary_rows();
}

bool Associator::find_from(bool coarse, const Eigen::Isometry3d& T, Eigen::Isometry3d* T_start,
                           bool leave_out_boundary) {
  find(coarse, *T_start, leave_out_boundary);
  if (table_.pairs > 0 || T_start->matrix() == T.matrix()) return false;
  *T_start = T;
  find(coarse, T, leave_out_boundary);
  return true;
}

void Associator::leave_out_boundary_rows() {
  const std::size_t k = static_cast<std::size_t>(table_.k);
  std::size_t left = 0;
  table_.left_out.resize(table_.count.size());  // within the room prepare() reserved
  for (std::size_t j = 0; j < table_.count.size(); ++j) {
    // Slot 0 holds the row's nearest target point, the lowest-indexed of those tied at its
    // distance (AssociationTable).
    const bool out = table_.count[j] > 0 && boundary_[table_.index[j * k]] != 0;
    table_.left_out[j] = out;
    left += out;
  }
  if (left == 0 || 2 * left > table_.matched) return;
  table_.any_left_out = true;
  table_.recount();
}

void Associator::associate(bool coarse, const Eigen::Isometry3d& T) {
  const PointCloud& cloud = coarse ? coarse_points_ : *source_;
  // From the coarse level's rows to every point's (within the room prepare() reserved): the
  // coarse points keep theirs when the coarse level was associated, else every row starts empty.
  if (!coarse && table_.count.size() != source_->size()) {
    if (use_cache_ && coarse_associated_) {
      spread_lists(settings_.coarse_stride, source_->size(), &cache_, &table_, settings_.parallel);
    } else {
      table_.resize(source_->size(), settings_.k);
      if (use_cache_) cache_.resize(source_->size(), cache_.capacity, settings_.parallel);
    }
  }
  if (use_cache_) {
    associate_cached(*tree_, *target_, cloud, T, settings_.radius, settings_.parallel, &cache_,
                     &table_);
  } else {
    detail::associate(*tree_, cloud, T, settings_.radius * settings_.radius, settings_.parallel,
                      &table_);
  }
  coarse_associated_ = coarse;
  pair_source_.normals = coarse ? &coarse_normals_ : source_normals_;
  pair_source_.R_target_source = T.linear();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
