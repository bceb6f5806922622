// A replica's durable store: a snapshot plus a log of every change joined since, in one LMDB environment,
// compacted in the background and loaded back into the replica on start.
#include "quiver/agents/replica/store/store.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "lmdb.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/state_parts.h"
#include "quiver/base/hash.h"
#include "quiver/base/byte_codec.h"
#include "quiver/agents/replica/store/records.h"

namespace quiver::agents::inline replica {

std::string_view to_string(Durability d) {
  switch (d) {
    case Durability::kNone: return "none";
    case Durability::kBatch: return "batch";
    case Durability::kAlways: return "always";
  }
  return "?";
}

Result<Durability> parse_durability(std::string_view s) {
  if (s == "none") return Durability::kNone;
  if (s == "batch") return Durability::kBatch;
  if (s == "always") return Durability::kAlways;
  return make_error(ErrorCode::kInvalidArgument,
                    "durability '" + std::string(s) + "': expected none, batch or always");
}

namespace fs = std::filesystem;
using namespace store;

namespace {

constexpr std::uint32_t kFormat = 1;
constexpr std::size_t kWakeBytes = 8u << 20;  // pending bytes that wake the writer early

std::vector<std::uint8_t> u64_bytes(std::uint64_t v) {
  std::vector<std::uint8_t> b;
  bytes::Writer(b).fixed64(v);
  return b;
}

}  // namespace

struct Store::Impl {
  StoreOptions opt;
  std::string where;  // "store DIR"
  graph::ReplicaId self;
  int lock_fd = -1;
  MDB_env* env = nullptr;
  MDB_dbi meta = 0, log = 0, snap = 0;

  mutable std::mutex mu;
  std::condition_variable wake, done;
  std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>> pending;
  std::size_t pending_bytes = 0;
  std::uint64_t next_record = 1;   // number of the next appended record
  std::uint64_t written = 0;       // records up to this number are in the log
  std::uint64_t synced = 0;        // ... and flushed
  std::uint64_t flush_wanted = 0;  // sync() waits for `synced` to reach this
  std::size_t log_bytes = 0;       // log bytes since the snapshot
  std::size_t snapshot_bytes = 0;
  bool compact_wanted = false;
  std::uint64_t compact_passes = 0;
  bool stopping = false;
  Status health;
  StoreStats stats;
  std::thread worker;

  ~Impl() {
    {
      std::lock_guard<std::mutex> l(mu);
      stopping = true;
    }
    wake.notify_all();
    if (worker.joinable()) worker.join();
    if (env != nullptr) mdb_env_close(env);
    if (lock_fd >= 0) ::close(lock_fd);
  }

  Status open_env() {
    if (int rc = mdb_env_create(&env); rc != 0) return lmdb_error(where, "mdb_env_create", rc);
    mdb_env_set_maxdbs(env, 4);
    if (int rc = mdb_env_set_mapsize(env, opt.map_bytes); rc != 0) return lmdb_error(where, "mdb_env_set_mapsize", rc);
    // We flush ourselves (mdb_env_sync) when the policy says so.
    if (int rc = mdb_env_open(env, opt.dir.c_str(), MDB_NOSYNC | MDB_NOTLS, 0644); rc != 0)
      return lmdb_error(where, "mdb_env_open", rc);
    // A truncated file would fault when its missing pages are read through the map: check its
    // length against the pages LMDB's meta page says are in use, before anything is read.
    MDB_envinfo info;
    MDB_stat st;
    mdb_env_info(env, &info);
    mdb_env_stat(env, &st);
    struct stat fst;
    const std::string data = (fs::path(opt.dir) / "data.mdb").string();
    if (::stat(data.c_str(), &fst) != 0) return make_error(ErrorCode::kIo, where + ": cannot stat " + data);
    const std::uint64_t needed = (static_cast<std::uint64_t>(info.me_last_pgno) + 1) * st.ms_psize;
    if (static_cast<std::uint64_t>(fst.st_size) < needed)
      return make_error(ErrorCode::kTruncated, where + ": data.mdb holds " + std::to_string(fst.st_size) +
                                                   " bytes but its pages in use end at byte " +
                                                   std::to_string(needed) + " (the file was truncated)");
    return {};
  }

  Status sync_env() {
    if (int rc = mdb_env_sync(env, 1); rc != 0) return lmdb_error(where, "mdb_env_sync", rc);
    std::lock_guard<std::mutex> l(mu);
    ++stats.syncs;
    return {};
  }

  // The fault to inject into a write (StoreOptions::faults), if any.
  StoreFault fault(StoreWrite::What what, std::size_t bytes, std::uint64_t first = 0, std::uint64_t last = 0) const {
    if (!opt.faults.before_write) return {};
    return opt.faults.before_write(StoreWrite{what, bytes, first, last});
  }

  // Writes records in one transaction.
  Status write(const std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>>& recs) {
    std::size_t bytes = 0;
    for (const auto& r : recs) bytes += r.second.size();
    const StoreFault f = fault(StoreWrite::What::kLog, bytes, recs.front().first, recs.back().first);
    if (f.kind == StoreFault::Kind::kNoSpace) return lmdb_error(where, "mdb_put (log)", ENOSPC);
    if (f.kind == StoreFault::Kind::kLie) return {};
    Txn t;
    if (Status s = t.begin(env, false, where); !s.ok()) return s;
    std::vector<std::uint8_t> torn;
    for (const auto& [n, bytes] : recs) {
      auto key = record_key(n);
      MDB_val k = val(key), v = val(bytes);
      if (f.kind == StoreFault::Kind::kTear && n == recs.back().first) {
        torn = bytes;
        if (f.flip) torn[f.keep % torn.size()] ^= 0xff;
        else torn.resize(std::min(f.keep, torn.size()));
        v = val(torn);
      }
      if (int rc = mdb_put(t.get(), log, &k, &v, MDB_APPEND); rc != 0) return lmdb_error(where, "mdb_put (log)", rc);
    }
    if (Status s = t.commit(where); !s.ok()) return s;
    if (f.kind == StoreFault::Kind::kTear)
      return make_error(ErrorCode::kIo, where + ": the power failed while log record " +
                                            std::to_string(recs.back().first) + " was written (a torn write)");
    return {};
  }

  // Under `always`: a write failed; the commit it belongs to must not return (fail-stop).
  void fail_stop(const Status& s) {
    if (opt.faults.fail_stop) return opt.faults.fail_stop(s.error());
    std::fprintf(stderr, "quiver: %s: a write under durability 'always' failed, stopping: %s\n", where.c_str(),
                 s.error().to_string().c_str());
    std::abort();
  }

  void append(std::vector<std::uint8_t> rec) {
    std::unique_lock<std::mutex> l(mu);
    const std::uint64_t n = next_record++;
    ++stats.records_appended;
    stats.bytes_appended += rec.size();
    log_bytes += rec.size();
    if (opt.durability == Durability::kAlways) {
      // Every commit is written whatever happened before (a compaction that failed for want of
      // space must not make later commits return unwritten).
      l.unlock();
      std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>> one;
      one.emplace_back(n, std::move(rec));
      Status s = write(one);
      if (s.ok()) s = sync_env();
      if (!s.ok()) {
        // Fail-stop: this commit has not returned and its delta is not published yet.
        {
          std::lock_guard<std::mutex> g(mu);
          if (health.ok()) health = s;
        }
        fail_stop(s);
        return;
      }
      l.lock();
      written = synced = n;
      ++stats.flushes;
      if (compaction_due()) wake.notify_one();
      return;
    }
    if (!health.ok()) return;
    pending_bytes += rec.size();
    pending.emplace_back(n, std::move(rec));
    if (pending_bytes >= kWakeBytes) wake.notify_one();
  }

  bool compaction_due() const {
    return opt.compact_log_bytes > 0 && log_bytes >= opt.compact_log_bytes && log_bytes > snapshot_bytes;
  }

  // The store's thread: writes what is pending every batch_ns (none, batch), compacts.
  void run() {
    std::unique_lock<std::mutex> l(mu);
    while (true) {
      // After an error nothing more is written or compacted: a flush that cannot happen must not
      // wake this thread (it would spin).
      auto ready = [&] {
        return stopping || compact_wanted || pending_bytes >= kWakeBytes ||
               (health.ok() && (flush_wanted > synced ||
                                (opt.durability == Durability::kAlways && compaction_due())));
      };
      if (opt.batch_ns > 0) wake.wait_for(l, std::chrono::nanoseconds(opt.batch_ns), ready);
      else wake.wait(l, ready);
      if (!pending.empty()) {
        auto batch = std::move(pending);
        pending.clear();
        pending_bytes = 0;
        const std::uint64_t last = batch.back().first;
        l.unlock();
        Status s = write(batch);
        if (s.ok() && opt.durability != Durability::kNone) s = sync_env();
        l.lock();
        if (!s.ok()) {
          if (health.ok()) health = s;
        } else {
          written = last;
          ++stats.flushes;
          if (opt.durability != Durability::kNone) synced = last;
        }
      }
      if (flush_wanted > synced && health.ok()) {
        l.unlock();
        Status s = sync_env();
        l.lock();
        if (s.ok()) synced = written;
        else if (health.ok()) health = s;
      }
      if ((compact_wanted || compaction_due()) && health.ok()) {
        const std::uint64_t upto = written;
        l.unlock();
        Status s = compact_upto(upto);
        l.lock();
        if (!s.ok() && health.ok()) health = s;
        compact_wanted = false;
        ++compact_passes;
      }
      done.notify_all();
      if (stopping && pending.empty()) return;
    }
  }

  // Replays the snapshot and the log records up to `upto` (0: all) into `g`.
  Status replay(MDB_txn* txn, graph::Graph& g, crdt::CausalContext& applied, std::uint64_t upto,
                std::uint64_t& records, std::size_t& bytes_after_snapshot, std::size_t& snap_bytes) {
    graph::GraphDelta scratch;
    std::uint64_t after = 0;
    MDB_val k = val(std::string_view("s")), v;
    if (int rc = mdb_get(txn, snap, &k, &v); rc == 0) {
      auto s = decode_snapshot(bytes_of(v), where + ": snapshot");
      if (!s.ok()) return s.error();
      // Joined a few hundred ops at a time: a large snapshot is never held decoded whole.
      if (Status d = graph::merge_state(g, s->state, scratch); !d.ok())
        return make_error(ErrorCode::kMalformed, where + ": snapshot: " + d.error().message);
      applied.join(s->applied);
      after = s->upto;
      snap_bytes = v.mv_size;
    } else if (rc != MDB_NOTFOUND) {
      return lmdb_error(where, "mdb_get (snapshot)", rc);
    }
    MDB_cursor* c = nullptr;
    if (int rc = mdb_cursor_open(txn, log, &c); rc != 0) return lmdb_error(where, "mdb_cursor_open", rc);
    struct Closer {
      MDB_cursor* c;
      ~Closer() { mdb_cursor_close(c); }
    } closer{c};
    auto first = record_key(after + 1);
    k = val(first);
    int rc = mdb_cursor_get(c, &k, &v, MDB_SET_RANGE);
    std::uint64_t expect = after + 1;
    for (; rc == 0; rc = mdb_cursor_get(c, &k, &v, MDB_NEXT)) {
      if (k.mv_size != 8) return make_error(ErrorCode::kMalformed, where + ": a log key of " +
                                                                       std::to_string(k.mv_size) + " bytes");
      const std::uint64_t n = record_number(bytes_of(k));
      if (upto != 0 && n > upto) break;
      const std::string what = where + ": log record " + std::to_string(n);
      if (n != expect)
        return make_error(ErrorCode::kMalformed, what + ": records " + std::to_string(expect) + ".." +
                                                     std::to_string(n - 1) + " are missing");
      ++expect;
      auto rec = decode_record(bytes_of(v), what);
      if (!rec.ok()) return rec.error();
      if (rec->kind != RecordKind::kSkipped) {
        if (Status d = graph::decode(rec->payload, scratch); !d.ok())
          return make_error(ErrorCode::kMalformed, what + ": " + d.error().message);
        const auto want = rec->kind == RecordKind::kDelta ? graph::GraphDelta::Kind::kDelta
                                                          : graph::GraphDelta::Kind::kState;
        if (scratch.kind != want) return make_error(ErrorCode::kMalformed, what + ": the payload is of another kind");
        g.merge(scratch);
      }
      if (rec->kind == RecordKind::kState) applied.join(rec->applied);
      else applied.add_range(rec->origin, rec->lo, rec->hi);
      ++records;
      bytes_after_snapshot += v.mv_size;
    }
    if (rc != 0 && rc != MDB_NOTFOUND) return lmdb_error(where, "mdb_cursor_get (log)", rc);
    return {};
  }

  // Folds the log up to record `upto` into a new snapshot, off the owner thread: a private graph
  // is rebuilt from the store itself, so the agent's replica is never touched.
  Status compact_upto(std::uint64_t upto) {
    if (upto == 0) return {};
    graph::Graph shadow(self);
    crdt::CausalContext applied;
    std::uint64_t records = 0;
    std::size_t log_read = 0, snap_read = 0;
    {
      Txn t;
      if (Status s = t.begin(env, true, where); !s.ok()) return s;
      if (Status s = replay(t.get(), shadow, applied, upto, records, log_read, snap_read); !s.ok()) return s;
    }
    std::vector<std::uint8_t> state;
    graph::encode_state(shadow, {}, state);
    std::vector<std::uint8_t> snapshot = encode_snapshot(upto, applied, state);
    if (fault(StoreWrite::What::kSnapshot, snapshot.size()).kind == StoreFault::Kind::kNoSpace)
      return lmdb_error(where, "mdb_put (snapshot)", ENOSPC);
    Txn t;
    if (Status s = t.begin(env, false, where); !s.ok()) return s;
    MDB_val k = val(std::string_view("s")), v = val(snapshot);
    if (int rc = mdb_put(t.get(), snap, &k, &v, 0); rc != 0) return lmdb_error(where, "mdb_put (snapshot)", rc);
    MDB_cursor* c = nullptr;
    if (int rc = mdb_cursor_open(t.get(), log, &c); rc != 0) return lmdb_error(where, "mdb_cursor_open", rc);
    MDB_val ck, cv;
    while (mdb_cursor_get(c, &ck, &cv, MDB_FIRST) == 0 && record_number(bytes_of(ck)) <= upto) {
      if (int rc = mdb_cursor_del(c, 0); rc != 0) {
        mdb_cursor_close(c);
        return lmdb_error(where, "mdb_cursor_del (log)", rc);
      }
    }
    mdb_cursor_close(c);
    if (Status s = t.commit(where); !s.ok()) return s;
    if (opt.durability != Durability::kNone)
      if (Status s = sync_env(); !s.ok()) return s;
    std::lock_guard<std::mutex> l(mu);
    ++stats.compactions;
    snapshot_bytes = snapshot.size();
    log_bytes = log_bytes > log_read ? log_bytes - log_read : 0;
    return {};
  }
};

Store::Store() : impl_(std::make_unique<Impl>()) {}
Store::~Store() {
  if (impl_) (void)sync();
}

Result<std::unique_ptr<Store>> Store::open(const StoreOptions& opt, std::string_view name,
                                           std::uint64_t fresh_incarnation) {
  if (opt.dir.empty()) return make_error(ErrorCode::kInvalidArgument, "store: no directory given");
  if (name.empty()) return make_error(ErrorCode::kInvalidArgument, "store " + opt.dir + ": the agent's name is empty");
  std::unique_ptr<Store> s(new Store());
  Impl& m = *s->impl_;
  m.opt = opt;
  m.where = "store " + opt.dir;
  std::error_code ec;
  fs::create_directories(opt.dir, ec);
  if (ec) return make_error(ErrorCode::kIo, m.where + ": cannot create the directory: " + ec.message());
  const std::string lock = (fs::path(opt.dir) / "quiver.lock").string();
  m.lock_fd = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (m.lock_fd < 0) return make_error(ErrorCode::kIo, m.where + ": cannot open " + lock);
  if (::flock(m.lock_fd, LOCK_EX | LOCK_NB) != 0)
    return make_error(ErrorCode::kAlreadyExists, m.where + ": another process has it open");
  const bool created = !fs::exists(fs::path(opt.dir) / "data.mdb");
  if (Status st = m.open_env(); !st.ok()) return st.error();

  Txn t;
  if (Status st = t.begin(m.env, false, m.where); !st.ok()) return st.error();
  for (auto [dbi, db] : {std::pair{&m.meta, "meta"}, std::pair{&m.log, "log"}, std::pair{&m.snap, "snapshot"}})
    if (int rc = mdb_dbi_open(t.get(), db, MDB_CREATE, dbi); rc != 0) return lmdb_error(m.where, "mdb_dbi_open", rc);
  auto get = [&](std::string_view key) -> std::optional<std::span<const std::uint8_t>> {
    MDB_val k = val(key), v;
    if (mdb_get(t.get(), m.meta, &k, &v) != 0) return std::nullopt;
    return bytes_of(v);
  };
  auto get_u64 = [&](std::string_view key) -> std::optional<std::uint64_t> {
    auto b = get(key);
    if (!b || b->size() != 8) return std::nullopt;
    bytes::Reader r(*b, key);
    return r.fixed64("value");
  };
  StoreOpening& o = s->opening_;
  o.created = created;
  bool always_kept = false;
  if (!created) {
    auto format = get_u64("format");
    if (!format) return make_error(ErrorCode::kMalformed, m.where + ": no format record (not a Quiver store, or damaged)");
    if (*format != kFormat)
      return make_error(ErrorCode::kUnsupportedVersion, m.where + ": store format " + std::to_string(*format) +
                                                            " (this build reads format " + std::to_string(kFormat) + ")");
    auto stored = get("name");
    const std::string stored_name = stored ? std::string(stored->begin(), stored->end()) : std::string();
    if (stored_name != name)
      return make_error(ErrorCode::kInvalidArgument, m.where + ": it belongs to agent '" + stored_name +
                                                         "', not '" + std::string(name) + "'");
    auto inc = get_u64("incarnation");
    auto always = get_u64("always");
    if (!inc || !always) return make_error(ErrorCode::kMalformed, m.where + ": its meta records are incomplete");
    always_kept = *always == 1;
    o.incarnation_kept = always_kept;
    o.incarnation = always_kept ? *inc : fresh_incarnation;
  } else {
    o.incarnation = fresh_incarnation;
  }
  auto put = [&](std::string_view key, std::span<const std::uint8_t> value) -> Status {
    MDB_val k = val(key), v = val(value);
    if (int rc = mdb_put(t.get(), m.meta, &k, &v, 0); rc != 0) return lmdb_error(m.where, "mdb_put (meta)", rc);
    return {};
  };
  std::size_t meta_bytes = 32 + name.size();
  if (m.fault(StoreWrite::What::kMeta, meta_bytes).kind == StoreFault::Kind::kNoSpace)
    return lmdb_error(m.where, "mdb_put (meta)", ENOSPC);
  const std::string name_s(name);
  const std::span<const std::uint8_t> name_b(reinterpret_cast<const std::uint8_t*>(name_s.data()), name_s.size());
  for (Status st : {put("format", u64_bytes(kFormat)), put("name", name_b), put("incarnation", u64_bytes(o.incarnation)),
                    put("always", u64_bytes(opt.durability == Durability::kAlways ? 1 : 0))})
    if (!st.ok()) return st.error();
  // The next record's number.
  {
    MDB_cursor* c = nullptr;
    if (int rc = mdb_cursor_open(t.get(), m.log, &c); rc != 0) return lmdb_error(m.where, "mdb_cursor_open", rc);
    MDB_val k, v;
    if (mdb_cursor_get(c, &k, &v, MDB_LAST) == 0 && k.mv_size == 8) {
      const std::uint64_t last = record_number(bytes_of(k));
      m.next_record = last + 1;
      // A last record that does not verify is the trace of a write the power cut: dropped, and
      // named. Under `always` it was never acknowledged; the replica takes a new incarnation
      // all the same (the store cannot prove what the write held).
      if (auto rec = decode_record(bytes_of(v), m.where + ": log record " + std::to_string(last)); !rec.ok()) {
        if (int rc = mdb_cursor_del(c, 0); rc != 0) {
          mdb_cursor_close(c);
          return lmdb_error(m.where, "mdb_cursor_del (torn log record)", rc);
        }
        o.torn_tail = rec.error().message + "; dropped as a torn write";
        m.next_record = last;
        if (o.incarnation_kept) {
          o.incarnation_kept = false;
          o.incarnation = fresh_incarnation;
          if (Status st = put("incarnation", u64_bytes(o.incarnation)); !st.ok()) {
            mdb_cursor_close(c);
            return st.error();
          }
        }
      }
    }
    mdb_cursor_close(c);
    MDB_val sk = val(std::string_view("s")), sv;
    if (mdb_get(t.get(), m.snap, &sk, &sv) == 0) {
      auto snap = decode_snapshot(bytes_of(sv), m.where + ": snapshot");
      if (!snap.ok()) return snap.error();
      m.next_record = std::max(m.next_record, snap->upto + 1);
      m.snapshot_bytes = o.snapshot_bytes = sv.mv_size;
    }
  }
  if (Status st = t.commit(m.where); !st.ok()) return st.error();
  // The incarnation we run under is on disk before anything is published under it.
  if (Status st = m.sync_env(); !st.ok()) return st.error();
  m.written = m.synced = m.next_record - 1;
  m.self = graph::ReplicaId{fnv1a64(name), o.incarnation};
  m.worker = std::thread([&m] { m.run(); });
  return s;
}

Result<crdt::CausalContext> Store::load(graph::Graph& g) {
  Impl& m = *impl_;
  crdt::CausalContext applied;
  Txn t;
  if (Status s = t.begin(m.env, true, m.where); !s.ok()) return s.error();
  std::uint64_t records = 0;
  std::size_t log_bytes = 0, snap_bytes = 0;
  if (Status s = m.replay(t.get(), g, applied, 0, records, log_bytes, snap_bytes); !s.ok()) return s.error();
  std::lock_guard<std::mutex> l(m.mu);
  m.stats.records_loaded = records;
  m.log_bytes = log_bytes;
  opening_.records = records;
  return applied;
}

void Store::local(std::uint64_t seq, std::span<const std::uint8_t> delta) {
  impl_->append(encode_delta_record(impl_->self, seq, seq, delta));
}

void Store::remote(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
                   std::span<const std::uint8_t> delta) {
  impl_->append(encode_delta_record(origin, lo, hi, delta));
}

void Store::state(std::span<const std::uint8_t> fragment, const crdt::CausalContext& applied) {
  impl_->append(encode_state_record(applied, fragment));
}

void Store::skipped(std::uint64_t lo, std::uint64_t hi) { impl_->append(encode_skipped_record(impl_->self, lo, hi)); }

Status Store::sync() {
  Impl& m = *impl_;
  std::unique_lock<std::mutex> l(m.mu);
  m.flush_wanted = m.next_record - 1;
  m.wake.notify_one();
  m.done.wait(l, [&] { return !m.health.ok() || (m.pending.empty() && m.synced >= m.flush_wanted); });
  return m.health;
}

Status Store::compact() {
  Impl& m = *impl_;
  if (Status s = sync(); !s.ok()) return s;
  std::unique_lock<std::mutex> l(m.mu);
  const std::uint64_t before = m.compact_passes;
  m.compact_wanted = true;
  m.wake.notify_one();
  m.done.wait(l, [&] { return !m.health.ok() || m.compact_passes > before; });
  return m.health;
}

Status Store::health() const {
  std::lock_guard<std::mutex> l(impl_->mu);
  return impl_->health;
}

StoreStats Store::stats() const {
  std::lock_guard<std::mutex> l(impl_->mu);
  return impl_->stats;
}

const StoreOptions& Store::options() const { return impl_->opt; }

Result<std::string> Store::set_aside(const std::string& dir) {
  std::error_code ec;
  for (int n = 1; n < 1000; ++n) {
    const std::string to = dir + ".corrupt-" + std::to_string(n);
    if (fs::exists(to, ec)) continue;
    fs::rename(dir, to, ec);
    if (ec) return make_error(ErrorCode::kIo, "store " + dir + ": cannot move it to " + to + ": " + ec.message());
    return to;
  }
  return make_error(ErrorCode::kIo, "store " + dir + ": too many stores set aside already");
}

}  // namespace quiver::agents
