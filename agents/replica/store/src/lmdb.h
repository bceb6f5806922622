#pragma once
// Small RAII helpers over LMDB's C API (liblmdb): transactions that abort unless committed, and
// errors that name the store and the call that failed.

#include <lmdb.h>

#include <span>
#include <string>

#include "quiver/base/result.h"

namespace quiver::agents::inline replica::store {

inline Error lmdb_error(const std::string& where, const char* call, int rc) {
  ErrorCode code = ErrorCode::kIo;
  if (rc == MDB_CORRUPTED || rc == MDB_PAGE_NOTFOUND || rc == MDB_BAD_TXN) code = ErrorCode::kMalformed;
  if (rc == MDB_INVALID) code = ErrorCode::kMalformed;
  if (rc == MDB_VERSION_MISMATCH) code = ErrorCode::kUnsupportedVersion;
  if (rc == MDB_MAP_FULL) code = ErrorCode::kTooLarge;
  return make_error(code, where + ": " + call + " failed: " + mdb_strerror(rc));
}

class Txn {
 public:
  Txn() = default;
  Txn(const Txn&) = delete;
  Txn& operator=(const Txn&) = delete;
  ~Txn() {
    if (t_ != nullptr) mdb_txn_abort(t_);
  }
  Status begin(MDB_env* env, bool read_only, const std::string& where) {
    if (int rc = mdb_txn_begin(env, nullptr, read_only ? MDB_RDONLY : 0, &t_); rc != 0) {
      t_ = nullptr;
      return lmdb_error(where, "mdb_txn_begin", rc);
    }
    return {};
  }
  Status commit(const std::string& where) {
    int rc = mdb_txn_commit(t_);
    t_ = nullptr;
    if (rc != 0) return lmdb_error(where, "mdb_txn_commit", rc);
    return {};
  }
  MDB_txn* get() const { return t_; }

 private:
  MDB_txn* t_ = nullptr;
};

inline MDB_val val(std::span<const std::uint8_t> b) {
  return MDB_val{b.size(), const_cast<std::uint8_t*>(b.data())};
}
inline MDB_val val(std::string_view s) { return MDB_val{s.size(), const_cast<char*>(s.data())}; }
inline std::span<const std::uint8_t> bytes_of(const MDB_val& v) {
  return {static_cast<const std::uint8_t*>(v.mv_data), v.mv_size};
}

}  // namespace quiver::agents::inline replica::store
