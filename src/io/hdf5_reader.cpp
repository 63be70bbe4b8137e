#include "detail/hdf5_reader.hpp"

#include "cubecal/error.hpp"

namespace cubecal::io {

bool looks_like_hdf5(std::string_view head) noexcept {
  constexpr std::string_view kSignature("\x89HDF\r\n\x1a\n", 8);
  for (std::size_t at = 0; at + kSignature.size() <= head.size(); at = at == 0 ? 512 : 2 * at)
    if (head.substr(at, kSignature.size()) == kSignature) return true;
  return false;
}

}  // namespace cubecal::io

// The fuzz build leaves libhdf5 out: the library is not hardened against
// hostile files, and the fuzzers, which learn the signature from the
// comparison in looks_like_hdf5, would report its faults as the readers'.
#ifndef CUBECAL_FUZZ_WITHOUT_HDF5
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include "cubecal/error.hpp"
#include "detail/binary_table.hpp"

namespace cubecal::io {

namespace {

constexpr const char* kWrite =
    "write a numeric 1-D or 2-D dataset (or a 1-D compound of numbers) with h5py or the HDF5 library";

// The serial library is not thread-safe: one reader at a time.
std::mutex& library_mutex() {
  static std::mutex m;
  return m;
}

// An HDF5 identifier, closed with its kind's close function.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(close_, o.close_);
    return *this;
  }
  ~Handle() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
  }
  hid_t get() const noexcept { return id_; }
  bool valid() const noexcept { return id_ >= 0; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// The deepest description on the library's error stack (the cause), or "".
std::string library_error() {
  std::string deepest;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        auto* s = static_cast<std::string*>(data);
        if (s->empty() && e->desc != nullptr) *s = e->desc;
        return 0;
      },
      &deepest);
  H5Eclear2(H5E_DEFAULT);
  for (char& c : deepest)
    if (c == '\n' || c == '\r') c = ' ';
  return deepest;
}

[[noreturn]] void fail(const std::string& file, const std::string& what, const std::string& hint = kWrite) {
  throw InputError(file, 0, 0, what, hint);
}

[[noreturn]] void fail_library(const std::string& file, const std::string& what) {
  const std::string cause = library_error();
  fail(file, "HDF5: " + what + (cause.empty() ? "" : ": " + cause),
       "the file is truncated or damaged, or not written by an HDF5 library this one reads");
}

bool numeric_class(hid_t type) {
  const H5T_class_t c = H5Tget_class(type);
  return (c == H5T_INTEGER || c == H5T_FLOAT) && H5Tget_size(type) <= 8;
}

std::string type_text(hid_t type) {
  const std::size_t size = H5Tget_size(type);
  switch (H5Tget_class(type)) {
    case H5T_INTEGER: return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + std::to_string(8 * size);
    case H5T_FLOAT: return "float" + std::to_string(8 * size);
    case H5T_COMPOUND: {
      std::string s = "compound {";
      const int n = H5Tget_nmembers(type);
      for (int i = 0; i < n; ++i) {
        char* name = H5Tget_member_name(type, static_cast<unsigned>(i));
        const Handle m(H5Tget_member_type(type, static_cast<unsigned>(i)), H5Tclose);
        s += (i == 0 ? "" : ", ") + std::string(name != nullptr ? name : "?") + ": " +
             (m.valid() ? type_text(m.get()) : "?");
        H5free_memory(name);
      }
      return s + "}";
    }
    case H5T_STRING: return "string";
    case H5T_ENUM: return "enum";
    case H5T_ARRAY: return "array";
    default: return "other";
  }
}

struct Dataset {
  std::string path;  // "/imu/data"
  std::vector<hsize_t> dims;
  std::string type;
  bool candidate = false;  // numeric 1-D/2-D, or compound 1-D with a numeric member
  std::string described() const {
    std::string shape = "(";
    for (std::size_t i = 0; i < dims.size(); ++i) shape += (i ? ", " : "") + std::to_string(dims[i]);
    if (dims.size() == 1) shape += ",";
    return path + " " + shape + ") " + type;
  }
};

bool has_numeric_member(hid_t type) {
  const int n = H5Tget_nmembers(type);
  for (int i = 0; i < n; ++i) {
    const Handle m(H5Tget_member_type(type, static_cast<unsigned>(i)), H5Tclose);
    if (m.valid() && numeric_class(m.get())) return true;
  }
  return false;
}

Dataset describe(hid_t ds, std::string path) {
  Dataset d;
  d.path = std::move(path);
  const Handle space(H5Dget_space(ds), H5Sclose);
  const Handle type(H5Dget_type(ds), H5Tclose);
  if (!space.valid() || !type.valid()) return d;
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank > 0 && rank <= 32) {
    d.dims.resize(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space.get(), d.dims.data(), nullptr);
  }
  d.type = type_text(type.get());
  const bool compound = H5Tget_class(type.get()) == H5T_COMPOUND;
  d.candidate = (numeric_class(type.get()) && (rank == 1 || rank == 2)) ||
                (compound && rank == 1 && has_numeric_member(type.get()));
  return d;
}

// Every dataset of the file, by path.
std::vector<Dataset> datasets_of(hid_t file) {
  std::vector<Dataset> all;
  H5Lvisit(
      file, H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t group, const char* name, const H5L_info_t* info, void* data) -> herr_t {
        if (info->type != H5L_TYPE_HARD) return 0;
        const Handle obj(H5Oopen(group, name, H5P_DEFAULT), H5Oclose);
        if (!obj.valid() || H5Iget_type(obj.get()) != H5I_DATASET) return 0;
        std::string path(1, '/');  // (built in steps: GCC 12 warns wrongly of "/" + std::string)
        path += name;
        static_cast<std::vector<Dataset>*>(data)->push_back(describe(obj.get(), std::move(path)));
        return 0;
      },
      &all);
  H5Eclear2(H5E_DEFAULT);
  return all;
}

std::string listed(const std::vector<Dataset>& v) {
  if (v.empty()) return "none";
  std::string s;
  for (const auto& d : v) s += (s.empty() ? "" : "; ") + d.described();
  return s;
}

std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The values of a whole dataset of `dims` read as doubles (`mem`: the
// memory type), with a bound on what a small file may claim.
std::vector<double> read_doubles(hid_t ds, hid_t mem, std::size_t values, std::size_t file_bytes,
                                 const std::string& file, const std::string& path) {
  // A dataset of unwritten chunks reads as fill values: a few bytes may
  // claim terabytes. Compressed sensor data shrink far less than 1000x.
  const hsize_t stored = H5Dget_storage_size(ds);
  if (values > 0 && stored == 0) fail(file, "dataset " + path + " holds no written data");
  const double limit = 1000.0 * static_cast<double>(std::max<std::size_t>(file_bytes, std::size_t{1} << 20));
  if (8.0 * static_cast<double>(values) > limit)
    fail(file, "dataset " + path + " claims " + std::to_string(values) + " values in a file of " +
                   std::to_string(file_bytes) + " bytes");
  std::vector<double> v(values);
  if (values > 0 && H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    fail_library(file, "cannot read dataset " + path);
  return v;
}

// An infinite value is refused at its row and column; so is a NaN, unless
// `missing_as_nan` (--gaps skip: a missing sample, kept as NaN).
void check_finite(Table& t, const std::string& path, bool missing_as_nan, std::size_t first_row = 0) {
  for (std::size_t c = 0; c < t.data.size(); ++c) {
    auto& col = t.data[c];
    for (std::size_t r = 0; r < col.size(); ++r) {
      if (std::isfinite(col[r])) continue;
      const bool nan = std::isnan(col[r]);
      if (nan && missing_as_nan) {
        col[r] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      fail(t.file,
           std::string(nan ? "NaN" : "infinite value") + " in dataset " + path + " at row " +
               std::to_string(first_row + r + 1) + ", column " + std::to_string(c + 1) +
               (t.has_header ? " (" + t.header[c] + ")" : ""),
           nan ? detail::kNanSampleHint : "an invalid sample, never a missing one: cut the record there");
    }
  }
}

Table new_table(const std::string& file, std::size_t file_bytes) {
  Table t;
  t.file = file;
  t.binary = true;
  t.bytes = file_bytes;
  t.first_data_line = 0;
  return t;
}

void name_columns(Table& t, std::vector<std::string> names) {
  t.total_columns = t.data.size();
  t.has_header = !names.empty();
  t.header = names;
  for (std::size_t c = 0; c < t.total_columns; ++c) {
    t.indices.push_back(c);
    t.names.push_back(names.empty() ? "col" + std::to_string(c + 1) : names[c]);
  }
}

Table read_dataset(hid_t ds, const Dataset& d, const std::string& file, std::size_t file_bytes, bool missing_as_nan) {
  if (!d.candidate)
    fail(file, "dataset " + d.described() + " is not a numeric 1-D or 2-D dataset or a 1-D compound of numbers");
  Table t = new_table(file, file_bytes);
  const Handle type(H5Dget_type(ds), H5Tclose);
  if (!type.valid()) fail_library(file, "cannot read the type of dataset " + d.path);
  const std::size_t rows = static_cast<std::size_t>(d.dims[0]);
  if (H5Tget_class(type.get()) == H5T_COMPOUND) {
    // The numeric members, converted by name into a record of doubles.
    std::vector<std::string> names;
    const int n = H5Tget_nmembers(type.get());
    for (int i = 0; i < n; ++i) {
      const Handle m(H5Tget_member_type(type.get(), static_cast<unsigned>(i)), H5Tclose);
      if (!m.valid() || !numeric_class(m.get())) continue;
      char* name = H5Tget_member_name(type.get(), static_cast<unsigned>(i));
      if (name != nullptr) names.emplace_back(name);
      H5free_memory(name);
    }
    if (rows != 0 && names.size() > SIZE_MAX / 8 / rows) fail(file, "dataset " + d.described() + " is too large");
    const Handle mem(H5Tcreate(H5T_COMPOUND, 8 * names.size()), H5Tclose);
    for (std::size_t i = 0; i < names.size(); ++i)
      if (H5Tinsert(mem.get(), names[i].c_str(), 8 * i, H5T_NATIVE_DOUBLE) < 0)
        fail_library(file, "cannot read member " + names[i] + " of dataset " + d.path);
    const std::vector<double> v = read_doubles(ds, mem.get(), rows * names.size(), file_bytes, file, d.path);
    t.data.assign(names.size(), std::vector<double>(rows));
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < names.size(); ++c) t.data[c][r] = v[r * names.size() + c];
    name_columns(t, names);
  } else {
    const std::size_t cols = d.dims.size() == 2 ? static_cast<std::size_t>(d.dims[1]) : 1;
    if (cols == 0) fail(file, "dataset " + d.described() + " has no columns");
    if (rows != 0 && cols > SIZE_MAX / 8 / rows) fail(file, "dataset " + d.described() + " is too large");
    const std::vector<double> v = read_doubles(ds, H5T_NATIVE_DOUBLE, rows * cols, file_bytes, file, d.path);
    t.data.assign(cols, std::vector<double>(rows));
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) t.data[c][r] = v[r * cols + c];
    name_columns(t, d.dims.size() == 1 ? std::vector<std::string>{base_name(d.path)} : std::vector<std::string>{});
  }
  check_finite(t, d.path, missing_as_nan);
  return t;
}

// The names of a group's members, in the order of their names.
std::vector<std::string> group_members(hid_t group) {
  std::vector<std::string> members;
  H5Literate(
      group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &members);
  return members;
}

// A group of numeric 1-D datasets of one length: a named column each (in
// the order of their names).
Table read_group(hid_t group, const std::string& path, const std::string& file, std::size_t file_bytes,
                 bool missing_as_nan) {
  const std::vector<std::string> members = group_members(group);
  Table t = new_table(file, file_bytes);
  std::vector<std::string> names;
  std::optional<hsize_t> length;
  for (const auto& m : members) {
    const Handle ds(H5Dopen2(group, m.c_str(), H5P_DEFAULT), H5Dclose);
    const std::string member_path = (path.ends_with('/') ? path : path + "/") + m;
    if (!ds.valid()) {
      H5Eclear2(H5E_DEFAULT);
      fail(file, path + " is a group whose member " + m + " is not a dataset",
           "give a dataset with {dataset} PATH, or a group of numeric 1-D datasets of one length");
    }
    const Dataset d = describe(ds.get(), member_path);
    const Handle type(H5Dget_type(ds.get()), H5Tclose);
    if (d.dims.size() != 1 || !type.valid() || !numeric_class(type.get()))
      fail(file, path + " is a group whose member " + d.described() + " is not a numeric 1-D dataset",
           "give a dataset with {dataset} PATH, or a group of numeric 1-D datasets of one length");
    if (length && *length != d.dims[0])
      fail(file,
           "group " + path + ": " + d.described() + " differs in length from the members before it (" +
               std::to_string(*length) + ")",
           "give one of its datasets with {dataset} PATH");
    length = d.dims[0];
    t.data.push_back(
        read_doubles(ds.get(), H5T_NATIVE_DOUBLE, static_cast<std::size_t>(d.dims[0]), file_bytes, file, member_path));
    names.push_back(m);
  }
  if (names.empty()) fail(file, "group " + path + " holds no datasets", "give a dataset with {dataset} PATH");
  name_columns(t, names);
  check_finite(t, path, missing_as_nan);
  return t;
}

Table read_locked(std::string_view bytes, const std::string& file, const std::string& open_path,
                  const std::string& dataset, bool missing_as_nan) {
  // The library prints its error stack on stderr by default: off; the
  // problems become InputErrors.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  Handle f;
  if (!open_path.empty()) {
    f = Handle(H5Fopen(open_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  } else {
    const Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), 1 << 16, 0) < 0 ||
        H5Pset_file_image(fapl.get(), const_cast<char*>(bytes.data()), bytes.size()) < 0)
      fail_library(file, "cannot open the file in memory");
    f = Handle(H5Fopen("cubecal-memory.h5", H5F_ACC_RDONLY, fapl.get()), H5Fclose);
  }
  if (!f.valid()) fail_library(file, "cannot open the file");

  if (dataset.empty()) {
    const std::vector<Dataset> all = datasets_of(f.get());
    std::vector<const Dataset*> candidates;
    for (const auto& d : all)
      if (d.candidate) candidates.push_back(&d);
    if (candidates.size() != 1) {
      std::vector<Dataset> shown;
      for (const Dataset* d : candidates) shown.push_back(*d);
      if (candidates.empty()) fail(file, "no numeric 1-D or 2-D dataset; datasets are: " + listed(all), kWrite);
      fail(file, std::to_string(candidates.size()) + " numeric datasets: " + listed(shown),
           "choose one with {dataset} PATH");
    }
    const Handle ds(H5Dopen2(f.get(), candidates[0]->path.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) fail_library(file, "cannot open dataset " + candidates[0]->path);
    return read_dataset(ds.get(), *candidates[0], file, bytes.size(), missing_as_nan);
  }

  const Handle obj(H5Oopen(f.get(), dataset.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) {
    H5Eclear2(H5E_DEFAULT);
    fail(file, "dataset " + dataset + " not found; datasets are: " + listed(datasets_of(f.get())),
         "choose one of them with {dataset} PATH");
  }
  if (H5Iget_type(obj.get()) == H5I_GROUP) return read_group(obj.get(), dataset, file, bytes.size(), missing_as_nan);
  if (H5Iget_type(obj.get()) != H5I_DATASET)
    fail(file, dataset + " is neither a dataset nor a group", "choose a dataset with {dataset} PATH");
  const std::string path = dataset.starts_with('/') ? dataset : "/" + dataset;
  return read_dataset(obj.get(), describe(obj.get(), path), file, bytes.size(), missing_as_nan);
}

// The columns of a dataset (a numeric 1-D or 2-D one, a compound) or of a
// group's 1-D datasets, read by hyperslabs of rows.
struct SlabColumns {
  Handle file;
  std::vector<Handle> datasets;  // one, or a group's members
  std::vector<std::string> paths;
  Handle mem;             // the memory type (a compound of doubles), or invalid for doubles
  std::size_t width = 1;  // values per row of each dataset
  std::size_t rows = 0;
  std::vector<std::string> names;  // empty: col1..colN
  std::string path;                // of the dataset or group, for messages
};

void check_claimed(hid_t ds, std::size_t values, std::size_t file_bytes, const std::string& file,
                   const std::string& path) {
  const hsize_t stored = H5Dget_storage_size(ds);
  if (values > 0 && stored == 0) fail(file, "dataset " + path + " holds no written data");
  const double limit = 1000.0 * static_cast<double>(std::max<std::size_t>(file_bytes, std::size_t{1} << 20));
  if (8.0 * static_cast<double>(values) > limit)
    fail(file, "dataset " + path + " claims " + std::to_string(values) + " values in a file of " +
                   std::to_string(file_bytes) + " bytes");
}

// A dataset's columns, as read_dataset takes them.
void dataset_columns(SlabColumns& c, Handle ds, const Dataset& d, const std::string& file, std::size_t file_bytes) {
  if (!d.candidate)
    fail(file, "dataset " + d.described() + " is not a numeric 1-D or 2-D dataset or a 1-D compound of numbers");
  const Handle type(H5Dget_type(ds.get()), H5Tclose);
  if (!type.valid()) fail_library(file, "cannot read the type of dataset " + d.path);
  c.rows = static_cast<std::size_t>(d.dims[0]);
  c.path = d.path;
  if (H5Tget_class(type.get()) == H5T_COMPOUND) {
    const int n = H5Tget_nmembers(type.get());
    for (int i = 0; i < n; ++i) {
      const Handle m(H5Tget_member_type(type.get(), static_cast<unsigned>(i)), H5Tclose);
      if (!m.valid() || !numeric_class(m.get())) continue;
      char* name = H5Tget_member_name(type.get(), static_cast<unsigned>(i));
      if (name != nullptr) c.names.emplace_back(name);
      H5free_memory(name);
    }
    c.width = c.names.size();
    c.mem = Handle(H5Tcreate(H5T_COMPOUND, 8 * c.width), H5Tclose);
    for (std::size_t i = 0; i < c.width; ++i)
      if (H5Tinsert(c.mem.get(), c.names[i].c_str(), 8 * i, H5T_NATIVE_DOUBLE) < 0)
        fail_library(file, "cannot read member " + c.names[i] + " of dataset " + d.path);
  } else {
    c.width = d.dims.size() == 2 ? static_cast<std::size_t>(d.dims[1]) : 1;
    if (c.width == 0) fail(file, "dataset " + d.described() + " has no columns");
    if (d.dims.size() == 1) c.names = {base_name(d.path)};
  }
  if (c.rows != 0 && c.width > SIZE_MAX / 8 / c.rows) fail(file, "dataset " + d.described() + " is too large");
  check_claimed(ds.get(), c.rows * c.width, file_bytes, file, d.path);
  c.paths.push_back(d.path);
  c.datasets.push_back(std::move(ds));
}

// A group's members, as read_group takes them.
void group_columns(SlabColumns& c, hid_t group, const std::string& path, const std::string& file,
                   std::size_t file_bytes) {
  const std::vector<std::string> members = group_members(group);
  c.path = path;
  std::optional<hsize_t> length;
  for (const auto& m : members) {
    Handle ds(H5Dopen2(group, m.c_str(), H5P_DEFAULT), H5Dclose);
    const std::string member_path = (path.ends_with('/') ? path : path + "/") + m;
    const std::string hint = "give a dataset with {dataset} PATH, or a group of numeric 1-D datasets of one length";
    if (!ds.valid()) {
      H5Eclear2(H5E_DEFAULT);
      fail(file, path + " is a group whose member " + m + " is not a dataset", hint);
    }
    const Dataset d = describe(ds.get(), member_path);
    const Handle type(H5Dget_type(ds.get()), H5Tclose);
    if (d.dims.size() != 1 || !type.valid() || !numeric_class(type.get()))
      fail(file, path + " is a group whose member " + d.described() + " is not a numeric 1-D dataset", hint);
    if (length && *length != d.dims[0])
      fail(file,
           "group " + path + ": " + d.described() + " differs in length from the members before it (" +
               std::to_string(*length) + ")",
           "give one of its datasets with {dataset} PATH");
    length = d.dims[0];
    check_claimed(ds.get(), static_cast<std::size_t>(d.dims[0]), file_bytes, file, member_path);
    c.datasets.push_back(std::move(ds));
    c.paths.push_back(member_path);
    c.names.push_back(m);
  }
  if (c.names.empty()) fail(file, "group " + path + " holds no datasets", "give a dataset with {dataset} PATH");
  c.rows = static_cast<std::size_t>(*length);
}

// Rows [first, first + count) of dataset `ds` (`width` values a row) as doubles.
// A 1-D dataset's rows are its values (of a compound: `width` doubles each).
std::vector<double> read_slab(hid_t ds, hid_t mem, std::size_t width, bool two_d, std::size_t first, std::size_t count,
                              const std::string& file, const std::string& path) {
  std::vector<double> v(count * width);
  if (count == 0) return v;
  const Handle space(H5Dget_space(ds), H5Sclose);
  const hsize_t start[2] = {first, 0};
  const hsize_t size[2] = {count, width};
  const int rank = two_d ? 2 : 1;
  const Handle in_memory(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (!space.valid() || !in_memory.valid() ||
      H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) < 0 ||
      H5Dread(ds, mem, in_memory.get(), space.get(), H5P_DEFAULT, v.data()) < 0)
    fail_library(file, "cannot read rows " + std::to_string(first + 1) + " to " + std::to_string(first + count) +
                           " of dataset " + path);
  return v;
}

}  // namespace

struct Hdf5Rows::Impl {
  std::string file;
  std::size_t file_bytes = 0;
  SlabColumns c;
  bool group = false, two_d = false;
};

Hdf5Rows::Hdf5Rows(const std::string& path, const std::string& dataset) : impl_(std::make_unique<Impl>()) {
  const std::lock_guard<std::mutex> lock(library_mutex());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  Impl& m = *impl_;
  m.file = path;
  std::error_code ec;
  m.file_bytes = static_cast<std::size_t>(std::filesystem::file_size(path, ec));
  m.c.file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!m.c.file.valid()) fail_library(path, "cannot open the file");
  const hid_t f = m.c.file.get();
  if (dataset.empty()) {
    const std::vector<Dataset> all = datasets_of(f);
    std::vector<Dataset> candidates;
    for (const auto& d : all)
      if (d.candidate) candidates.push_back(d);
    if (candidates.empty()) fail(path, "no numeric 1-D or 2-D dataset; datasets are: " + listed(all), kWrite);
    if (candidates.size() != 1)
      fail(path, std::to_string(candidates.size()) + " numeric datasets: " + listed(candidates),
           "choose one with {dataset} PATH");
    Handle ds(H5Dopen2(f, candidates[0].path.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) fail_library(path, "cannot open dataset " + candidates[0].path);
    m.two_d = candidates[0].dims.size() == 2;
    dataset_columns(m.c, std::move(ds), candidates[0], path, m.file_bytes);
    return;
  }
  Handle obj(H5Oopen(f, dataset.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) {
    H5Eclear2(H5E_DEFAULT);
    fail(path, "dataset " + dataset + " not found; datasets are: " + listed(datasets_of(f)),
         "choose one of them with {dataset} PATH");
  }
  if (H5Iget_type(obj.get()) == H5I_GROUP) {
    m.group = true;
    group_columns(m.c, obj.get(), dataset, path, m.file_bytes);
    return;
  }
  if (H5Iget_type(obj.get()) != H5I_DATASET)
    fail(path, dataset + " is neither a dataset nor a group", "choose a dataset with {dataset} PATH");
  const Dataset d = describe(obj.get(), dataset.starts_with('/') ? dataset : "/" + dataset);
  Handle ds(H5Dopen2(f, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) fail_library(path, "cannot open dataset " + d.path);
  m.two_d = d.dims.size() == 2;
  dataset_columns(m.c, std::move(ds), d, path, m.file_bytes);
}

Hdf5Rows::~Hdf5Rows() {
  const std::lock_guard<std::mutex> lock(library_mutex());
  impl_.reset();
}

std::size_t Hdf5Rows::rows() const noexcept { return impl_->c.rows; }

Table Hdf5Rows::slab(std::size_t first, std::size_t count) const {
  const std::lock_guard<std::mutex> lock(library_mutex());
  const Impl& m = *impl_;
  const SlabColumns& c = m.c;
  Table t = new_table(m.file, m.file_bytes);
  if (m.group) {
    for (std::size_t k = 0; k < c.datasets.size(); ++k)
      t.data.push_back(read_slab(c.datasets[k].get(), H5T_NATIVE_DOUBLE, 1, false, first, count, m.file, c.paths[k]));
  } else {
    const hid_t mem = c.mem.valid() ? c.mem.get() : H5T_NATIVE_DOUBLE;
    const std::vector<double> v = read_slab(c.datasets[0].get(), mem, c.width, m.two_d, first, count, m.file, c.path);
    t.data.assign(c.width, std::vector<double>(count));
    for (std::size_t r = 0; r < count; ++r)
      for (std::size_t k = 0; k < c.width; ++k) t.data[k][r] = v[r * c.width + k];
  }
  name_columns(t, c.names);
  check_finite(t, c.path, false, first);
  return t;
}

Table read_hdf5(std::string_view bytes, const std::string& file, const std::string& open_path,
                const std::string& dataset, bool missing_as_nan) {
  const std::lock_guard<std::mutex> lock(library_mutex());
  return read_locked(bytes, file, open_path, dataset, missing_as_nan);
}

}  // namespace cubecal::io

#else

namespace cubecal::io {

Table read_hdf5(std::string_view, const std::string& file, const std::string&, const std::string&, bool) {
  throw InputError(file, 0, 0, "HDF5 files are not read by the fuzz build");
}

struct Hdf5Rows::Impl {};
Hdf5Rows::Hdf5Rows(const std::string& path, const std::string&) {
  throw InputError(path, 0, 0, "HDF5 files are not read by the fuzz build");
}
Hdf5Rows::~Hdf5Rows() = default;
std::size_t Hdf5Rows::rows() const noexcept { return 0; }
Table Hdf5Rows::slab(std::size_t, std::size_t) const { return {}; }

}  // namespace cubecal::io

#endif
