#include "ballagg/io/hdf5_handle.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

namespace ballagg::hdf5 {

void quiet_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

void no_library_exit_handler() { H5dont_atexit(); }

hid_t check(hid_t status, const std::string& what) {
  if (status < 0) {
    // The failure is reported by our exception: empty the thread's HDF5 error stack, which
    // would otherwise hold its messages until the next HDF5 call on this thread, and leak
    // them if the thread ends first (a frame writer's thread: BackgroundWriter).
    H5Eclear2(H5E_DEFAULT);
    throw std::runtime_error(fmt::format("{}: HDF5 error", what));
  }
  return status;
}

Handle group_creation_properties() {
  Handle p(check(H5Pcreate(H5P_GROUP_CREATE), "group properties"), H5Pclose);
  check(H5Pset_obj_track_times(p, false), "group properties");
  return p;
}

Handle dataset_creation_properties() {
  Handle p(check(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose);
  check(H5Pset_obj_track_times(p, false), "dataset properties");
  return p;
}

Handle create_group(hid_t parent, const std::string& name) {
  const Handle gcpl = group_creation_properties();
  return {check(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), "create group " + name), H5Gclose};
}

Handle open_group(hid_t parent, const std::string& name) {
  return {check(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), "no group " + name), H5Gclose};
}

Handle open_dataset(hid_t parent, const std::string& name) {
  return {check(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), "no dataset " + name), H5Dclose};
}

bool exists(hid_t parent, const std::string& path) {
  // Checks each link of the path in turn (H5Lexists fails on a missing intermediate group).
  std::string prefix;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t slash = path.find('/', start);
    if (!prefix.empty()) prefix += '/';
    prefix.append(path, start, slash == std::string::npos ? std::string::npos : slash - start);
    if (H5Lexists(parent, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return true;
}

namespace {

Handle string_type(std::size_t size) {
  Handle t(check(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  check(H5Tset_size(t, std::max<std::size_t>(size, 1)), "string type");
  check(H5Tset_cset(t, H5T_CSET_UTF8), "string type");
  return t;
}

Handle simple_space(const std::vector<hsize_t>& dims, const std::vector<hsize_t>& max = {}) {
  return {check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max.empty() ? nullptr : max.data()),
                "dataspace"),
          H5Sclose};
}

Handle scalar_space() { return {check(H5Screate(H5S_SCALAR), "dataspace"), H5Sclose}; }

template <class T>
hid_t native_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, float>) return H5T_NATIVE_FLOAT;
  else if constexpr (std::is_same_v<T, std::int64_t>) return H5T_NATIVE_INT64;
  else return H5T_NATIVE_INT32;
}

}  // namespace

void write_attribute(hid_t object, const std::string& name, const std::vector<std::int32_t>& values) {
  const Handle space = values.size() == 1 ? scalar_space() : simple_space({values.size()});
  const Handle a(check(H5Acreate2(object, name.c_str(), H5T_NATIVE_INT32, space, H5P_DEFAULT, H5P_DEFAULT),
                       "attribute " + name),
                 H5Aclose);
  check(H5Awrite(a, H5T_NATIVE_INT32, values.data()), "attribute " + name);
}

void write_attribute(hid_t object, const std::string& name, const std::string& value) {
  const Handle type = string_type(value.size());
  const Handle space = scalar_space();
  const Handle a(check(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), "attribute " + name),
                 H5Aclose);
  check(H5Awrite(a, type, value.data()), "attribute " + name);
}

void write_attribute(hid_t object, const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const std::string& v : values) width = std::max(width, v.size());
  std::string packed(width * values.size(), '\0');
  for (std::size_t k = 0; k < values.size(); ++k) packed.replace(k * width, values[k].size(), values[k]);
  const Handle type = string_type(width);
  check(H5Tset_strpad(type, H5T_STR_NULLPAD), "string type");
  const Handle space = simple_space({values.size()});
  const Handle a(check(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), "attribute " + name),
                 H5Aclose);
  check(H5Awrite(a, type, packed.data()), "attribute " + name);
}

void write_variable_string_attribute(hid_t object, const std::string& name, const std::string& value) {
  const Handle type(check(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  check(H5Tset_size(type, H5T_VARIABLE), "string type");
  check(H5Tset_cset(type, H5T_CSET_ASCII), "string type");
  const Handle space = scalar_space();
  const Handle a(check(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), "attribute " + name),
                 H5Aclose);
  const char* text = value.c_str();
  check(H5Awrite(a, type, &text), "attribute " + name);
}

std::vector<std::int32_t> read_int_attribute(hid_t object, const std::string& name) {
  const Handle a(check(H5Aopen(object, name.c_str(), H5P_DEFAULT), "no attribute " + name), H5Aclose);
  const Handle space(check(H5Aget_space(a), "attribute " + name), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<std::int32_t> values(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  check(H5Aread(a, H5T_NATIVE_INT32, values.data()), "attribute " + name);
  return values;
}

void write_string_dataset(hid_t parent, const std::string& name, const std::string& text) {
  const Handle type = string_type(text.size());
  check(H5Tset_strpad(type, H5T_STR_NULLPAD), "string type");
  const Handle space = scalar_space();
  const Handle dcpl = dataset_creation_properties();
  const Handle d(check(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), "dataset " + name),
                 H5Dclose);
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), "dataset " + name);
}

std::string read_string_dataset(hid_t parent, const std::string& name) {
  const Handle d = open_dataset(parent, name);
  const Handle type(check(H5Dget_type(d), "dataset " + name), H5Tclose);
  if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0)
    throw std::runtime_error(fmt::format("dataset {}: not a fixed-length string", name));
  std::string text(H5Tget_size(type), '\0');
  check(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), "dataset " + name);
  text.resize(text.find('\0') == std::string::npos ? text.size() : text.find('\0'));
  return text;
}

void write_dataset(hid_t parent, const std::string& name, const std::vector<double>& values) {
  const Handle space = simple_space({values.size()});
  const Handle dcpl = dataset_creation_properties();
  const Handle d(check(H5Dcreate2(parent, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                       "dataset " + name),
                 H5Dclose);
  check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "dataset " + name);
}

std::vector<hsize_t> dimensions(hid_t dataset) {
  const Handle space(check(H5Dget_space(dataset), "dataspace"), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

std::vector<double> read_doubles(hid_t parent, const std::string& name) {
  const Handle d = open_dataset(parent, name);
  const std::vector<hsize_t> dims = dimensions(d);
  const hsize_t n = std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
  std::vector<double> values(n);
  check(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "dataset " + name);
  return values;
}

Series::Series(hid_t parent, const std::string& name, hid_t type, std::vector<hsize_t> inner, hsize_t chunk_rows,
               Compression compression)
    : type_(type), inner_(std::move(inner)) {
  std::vector<hsize_t> dims{0}, max{H5S_UNLIMITED}, chunk{1};
  for (std::size_t k = 0; k < inner_.size(); ++k) {
    dims.push_back(inner_[k]);
    max.push_back(inner_[k]);
    chunk.push_back(k == 0 ? std::max<hsize_t>(1, std::min(chunk_rows, inner_[k])) : inner_[k]);
  }
  if (inner_.empty()) chunk[0] = chunk_rows;  // a series of scalars: records per chunk
  const Handle space = simple_space(dims, max);
  const Handle dcpl = dataset_creation_properties();
  check(H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data()), "chunks of " + name);
  if (compression == Compression::shuffle_deflate) {
    check(H5Pset_shuffle(dcpl), "shuffle filter of " + name);
    check(H5Pset_deflate(dcpl, 1), "deflate filter of " + name);
  }
  // Records are written whole, once: no chunk cache (HDF5 writes the chunks directly,
  // without copying them through the cache first).
  const Handle dapl(check(H5Pcreate(H5P_DATASET_ACCESS), "dataset access"), H5Pclose);
  check(H5Pset_chunk_cache(dapl, 0, 0, 1.0), "dataset access");
  dataset_ = Handle(check(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, dcpl, dapl), "dataset " + name),
                    H5Dclose);
}

Series::Series(hid_t parent, const std::string& name, hid_t type, std::vector<hsize_t> inner, hsize_t records)
    : type_(type), inner_(std::move(inner)), records_(records) {
  const Handle dapl(check(H5Pcreate(H5P_DATASET_ACCESS), "dataset access"), H5Pclose);
  check(H5Pset_chunk_cache(dapl, 0, 0, 1.0), "dataset access");
  dataset_ = Handle(check(H5Dopen2(parent, name.c_str(), dapl), "no dataset " + name), H5Dclose);
  std::vector<hsize_t> dims = dimensions(dataset_);
  const Handle stored(check(H5Dget_type(dataset_), "type of dataset " + name), H5Tclose);
  if (dims.size() != inner_.size() + 1 || !std::equal(inner_.begin(), inner_.end(), dims.begin() + 1) ||
      dims[0] < records || H5Tequal(stored, type_) <= 0)
    throw std::runtime_error(fmt::format("dataset {}: not the series a checkpoint refers to", name));
  dims[0] = records;
  check(H5Dset_extent(dataset_, dims.data()), "cut back dataset " + name);
}

void Series::append(const void* data) {
  add_record();
  write_rows(0, inner_.empty() ? 1 : inner_[0], data);
}

void Series::add_record() {
  std::vector<hsize_t> dims{records_ + 1};
  dims.insert(dims.end(), inner_.begin(), inner_.end());
  check(H5Dset_extent(dataset_, dims.data()), "extend dataset");
  ++records_;
}

void Series::write_rows(hsize_t first, hsize_t rows, const void* data) {
  if (records_ == 0) throw std::logic_error("Series::write_rows before add_record");
  // The selection: record records_ - 1, rows [first, first + rows), everything inward.
  std::vector<hsize_t> start{records_ - 1}, count{1};
  for (std::size_t k = 0; k < inner_.size(); ++k) {
    start.push_back(k == 0 ? first : 0);
    count.push_back(k == 0 ? rows : inner_[k]);
  }
  const Handle file_space(check(H5Dget_space(dataset_), "dataspace"), H5Sclose);
  check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr), "select");
  const std::vector<hsize_t> memory = count.size() > 1 ? std::vector<hsize_t>(count.begin() + 1, count.end())
                                                        : std::vector<hsize_t>{1};
  const Handle memory_space = simple_space(memory);
  check(H5Dwrite(dataset_, type_, memory_space, file_space, H5P_DEFAULT, data), "write record");
}

template <class T>
void read_record(hid_t dataset, hsize_t k, std::vector<T>& out) {
  const std::vector<hsize_t> dims = dimensions(dataset);
  if (dims.empty() || k >= dims[0]) throw std::runtime_error(fmt::format("record {} out of range", k));
  std::vector<hsize_t> start(dims.size(), 0), count = dims;
  start[0] = k;
  count[0] = 1;
  const hsize_t n = std::accumulate(count.begin(), count.end(), hsize_t{1}, std::multiplies<>());
  out.resize(n);
  const Handle file_space(check(H5Dget_space(dataset), "dataspace"), H5Sclose);
  check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr), "select");
  const Handle memory_space = simple_space({n});
  check(H5Dread(dataset, native_type<T>(), memory_space, file_space, H5P_DEFAULT, out.data()), "read record");
}

template void read_record<double>(hid_t, hsize_t, std::vector<double>&);
template void read_record<std::int32_t>(hid_t, hsize_t, std::vector<std::int32_t>&);
template void read_record<std::int64_t>(hid_t, hsize_t, std::vector<std::int64_t>&);

}  // namespace ballagg::hdf5
