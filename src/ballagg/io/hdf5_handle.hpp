#pragma once
// A thin layer over the HDF5 C API (libhdf5 from Debian): handles that close themselves,
// calls that throw with the failing operation named, and the few dataset shapes the H5MD
// files need. Used by the H5MD writer and reader only.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ballagg::hdf5 {

// Owns an HDF5 identifier and closes it with the right H5*close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }
  // Gives up ownership (the caller closes it and checks the status).
  hid_t release() {
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }
  void reset() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// Silences the library's own error printing (we throw instead) on the calling thread;
// call before any other call on that thread.
void quiet_errors();

// For a program that closes every HDF5 file itself (the ballagg binary), called before any
// other HDF5 call: no library exit handler. HDF5 1.10 (Debian 12) frees a file whose close
// failed (a full disk: the last flush fails) but keeps its ID, and its exit handler then
// crashes on it (HDFFV-11052, fixed in HDF5 1.14.1): after a failed write the program
// would end with a segmentation fault instead of its one-line error.
void no_library_exit_handler();

// Throws std::runtime_error("what: HDF5 error") when status < 0 (and clears HDF5's error
// stack of the thread); returns status.
hid_t check(hid_t status, const std::string& what);

Handle create_group(hid_t parent, const std::string& name);
Handle open_group(hid_t parent, const std::string& name);
Handle open_dataset(hid_t parent, const std::string& name);
bool exists(hid_t parent, const std::string& path);

// Attributes.
void write_attribute(hid_t object, const std::string& name, const std::vector<std::int32_t>& values);
void write_attribute(hid_t object, const std::string& name, const std::string& value);
void write_attribute(hid_t object, const std::string& name, const std::vector<std::string>& values);
// A scalar variable-length ASCII string: the type the H5MD units module gives `unit`
// attributes, and the one h5py reads as a Python str (a fixed-length one comes back as bytes).
void write_variable_string_attribute(hid_t object, const std::string& name, const std::string& value);
std::vector<std::int32_t> read_int_attribute(hid_t object, const std::string& name);

// Fixed datasets (time-independent data).
void write_string_dataset(hid_t parent, const std::string& name, const std::string& text);
std::string read_string_dataset(hid_t parent, const std::string& name);
void write_dataset(hid_t parent, const std::string& name, const std::vector<double>& values);
std::vector<double> read_doubles(hid_t parent, const std::string& name);
std::vector<hsize_t> dimensions(hid_t dataset);

// A dataset of shape [variable][inner...] that grows by one record at a time.
class Series {
 public:
  enum class Compression { none, shuffle_deflate };
  // `type` is a native type (H5T_NATIVE_DOUBLE, H5T_NATIVE_INT32, ...); `chunk_rows` is
  // how many of the inner dimension's first axis go in one chunk.
  Series(hid_t parent, const std::string& name, hid_t type, std::vector<hsize_t> inner, hsize_t chunk_rows,
         Compression compression);
  // Reopens the series `name` of an existing file, cut back to its first `records`
  // (a resumed run: records written after its checkpoint are dropped). Throws
  // std::runtime_error if it is not such a series (shape or type) or holds fewer records.
  Series(hid_t parent, const std::string& name, hid_t type, std::vector<hsize_t> inner, hsize_t records);
  // Appends one record of prod(inner) values of the native type at `data`.
  void append(const void* data);
  // Appends one record to be written in parts (write_rows); until then it holds zeros.
  void add_record();
  // Rows [first, first + rows) of the inner dimension's first axis of the last record.
  void write_rows(hsize_t first, hsize_t rows, const void* data);
  hid_t id() const { return dataset_; }
  hsize_t records() const { return records_; }

 private:
  Handle dataset_;
  hid_t type_;
  std::vector<hsize_t> inner_;
  hsize_t records_ = 0;
};

// Reads record k of a [variable][inner...] dataset into `out` (resized to prod(inner)).
template <class T>
void read_record(hid_t dataset, hsize_t k, std::vector<T>& out);

// Object creation properties shared by every group and dataset: no timestamps, so that
// the same run gives a byte-identical file.
Handle group_creation_properties();
Handle dataset_creation_properties();

}  // namespace ballagg::hdf5
