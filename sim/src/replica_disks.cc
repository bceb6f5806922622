// The replica simulator's durable stores on simulated disks (DiskFaults): each agent's store on
// a disk whose faults are decided in virtual time (full disks, torn writes, power cuts, a lying
// disk), fail-stop, restarts from the store, flushes and compactions, and the check that every
// acknowledged commit survives.
#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "replica_simulation.h"

namespace quiver::sim {

void Simulation::make_disks() {
  if (cfg_.disks.dir.empty()) {
    // In memory when we can: the disks are simulated, the host's fdatasync would only cost time.
    std::error_code ec;
    const std::filesystem::path base =
        std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
    std::string tmpl = (base / "quiver-sim-disks-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) {
      store_error("cannot create a temporary directory for the stores");
      return;
    }
    root_ = tmpl;
    own_dir_ = true;
  } else {
    root_ = cfg_.disks.dir;
  }
  for (int i = 0; i < cfg_.agents; ++i) {
    Disk& d = agents_[i].disk;
    d.dir = (std::filesystem::path(root_) / ("agent" + std::to_string(i))).string();
    d.rng = Rng(cfg_.seed ^ (0xd15c0000ULL + static_cast<std::uint64_t>(i)));
    d.lying = cfg_.disks.lying_disk && i == 0;
  }
}

void Simulation::store_error(const std::string& e) {
  if (result_.first_store_error.empty()) result_.first_store_error = "t=" + std::to_string(net_.now()) + "ns " + e;
  note(e);
}

// The fault the disk of agent `i` injects into a write. Called on the thread that writes:
// the owner's (always), or the store's while the owner waits in sync() (batch): in order.
agents::StoreFault Simulation::disk_fault(int i, const agents::StoreWrite& w) {
  using Kind = agents::StoreFault::Kind;
  Disk& d = agents_[i].disk;
  if (d.power_off) return {Kind::kNoSpace};
  const bool log = w.what == agents::StoreWrite::What::kLog;
  if (log && d.tear_next) {
    d.tear_next = false;
    d.torn = true;
    d.power_off = true;
    ++result_.torn_writes;
    agents::StoreFault f{Kind::kTear};
    f.flip = d.rng.chance(0.3);
    f.keep = static_cast<std::size_t>(d.rng.below(std::max<std::size_t>(1, w.bytes)));
    return f;
  }
  if (net_.now() >= d.full_from && net_.now() < d.full_until) {
    ++result_.writes_refused;
    return {Kind::kNoSpace};
  }
  if (log && d.lying) return {Kind::kLie};
  return {};
}

// Under `always` a write failed: the host stops at once (nothing leaves it from now on).
void Simulation::fail_stop(int i, const Error& e) {
  Agent& a = agents_[i];
  if (a.failing) return;
  a.failing = true;
  ++result_.fail_stops;
  net_.set_up(i, false);
  note("agent" + std::to_string(i) + " stops (fail-stop): " + e.message);
  net_.at(net_.now(), [this, i] {
    crash(i);
    restart_later(i, 20'000'000);
  });
}

void Simulation::restart_later(int i, std::int64_t after_ns) {
  boot_pending_[i] = true;
  net_.at(net_.now() + after_ns, [this, i] {
    boot_pending_[i] = false;
    if (!agents_[i].up) boot(i);
  });
}

// Opens agent i's store and loads its replica into a new graph. False: the disk refused (the
// caller retries later).
bool Simulation::open_store(int i, crdt::CausalContext& applied) {
  Agent& a = agents_[i];
  agents::StoreOptions so;
  so.dir = a.disk.dir;
  so.durability = cfg_.disks.durability;
  so.batch_ns = 0;            // flushed by the simulator, in virtual time
  so.compact_log_bytes = 0;   // compacted by the simulator, in virtual time
  so.map_bytes = std::size_t{1} << 30;
  so.faults.before_write = [this, i](const agents::StoreWrite& w) { return disk_fault(i, w); };
  so.faults.fail_stop = [this, i](const Error& e) { fail_stop(i, e); };
  const std::string name = "agent" + std::to_string(i);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::uint64_t fresh = a.last_incarnation + 1;
    auto s = agents::Store::open(so, name, fresh);
    Error err;
    if (s.ok()) {
      a.store = std::move(*s);
      a.incarnation = a.store->opening().incarnation;
      a.last_incarnation = std::max(a.last_incarnation, a.incarnation);
      a.graph = std::make_unique<graph::Graph>(graph::ReplicaId{a.agent_id, a.incarnation});
      auto loaded = a.store->load(*a.graph);
      if (loaded.ok()) {
        applied = std::move(*loaded);
        ++result_.store_reloads;
        result_.records_reloaded += a.store->opening().records;
        if (!a.store->opening().torn_tail.empty()) {
          ++result_.torn_tails_dropped;
          note(name + ": " + a.store->opening().torn_tail);
        }
        return true;
      }
      err = loaded.error();
      a.store.reset();
      a.graph.reset();
    } else {
      err = s.error();
    }
    if (err.code != ErrorCode::kMalformed && err.code != ErrorCode::kTruncated &&
        err.code != ErrorCode::kUnsupportedVersion) {
      ++result_.restarts_refused;
      note(name + " cannot open its store, retries: " + err.to_string());
      return false;
    }
    // Damage: as DdsReplica does, set the store aside and start empty, filled by the peers.
    ++result_.stores_set_aside;
    store_error(name + ": " + err.to_string() + "; the store is set aside");
    if (auto aside = agents::Store::set_aside(a.disk.dir); !aside.ok()) {
      store_error(aside.error().to_string());
      return false;
    }
  }
  return false;
}

// Under `always`: every commit agent i acknowledged must be in `have`.
void Simulation::check_acked(int i, const crdt::CausalContext& have, const std::string& where) {
  std::uint64_t lost = 0;
  std::string first;
  agents_[i].acked.for_each_range([&](const graph::ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    for (std::uint64_t c = lo; c <= hi; ++c)
      if (!have.contains(r, c)) {
        if (first.empty()) first = r.to_string() + ":" + std::to_string(c);
        ++lost;
      }
  });
  if (lost == 0) return;
  result_.acked_lost += lost;
  const std::string line = "agent" + std::to_string(i) + ": " + std::to_string(lost) +
                           " acknowledged commits missing from " + where + " (first " + first + ")";
  if (result_.first_acked_lost.empty()) result_.first_acked_lost = "t=" + std::to_string(net_.now()) + "ns " + line;
  note(line);
}

void Simulation::plan_disk_faults(std::int64_t work_end) {
  const DiskFaults& d = cfg_.disks;
  // Flushes (batch) and compactions, each store on its own phase.
  for (int i = 0; i < cfg_.agents; ++i) {
    if (d.durability != agents::Durability::kAlways)
      every(static_cast<std::int64_t>(rng_.below(d.flush_ns)) + 1, d.flush_ns, [this, i] { flush(i); });
    every(static_cast<std::int64_t>(rng_.below(d.compact_ns)) + 1, d.compact_ns, [this, i] { compact(i); });
  }
  if (d.disk_full) {
    const int episodes = 1 + static_cast<int>(rng_.below(3));
    for (int e = 0; e < episodes; ++e) {
      const int who = static_cast<int>(rng_.below(cfg_.agents));
      const std::int64_t from = static_cast<std::int64_t>(rng_.below(work_end));
      const std::int64_t len = 30'000'000 + static_cast<std::int64_t>(rng_.below(600'000'000));
      net_.at(from, [this, who, len] {
        Disk& k = agents_[who].disk;
        k.full_from = net_.now();
        k.full_until = net_.now() + len;
        note("agent" + std::to_string(who) + "'s disk is full for " + std::to_string(len / 1'000'000) + " ms");
      });
      // Under batch the agent goes on without its store; a later power cut brings it back.
      if (d.durability != agents::Durability::kAlways && rng_.chance(0.5)) {
        const std::int64_t cut = from + len + static_cast<std::int64_t>(rng_.below(300'000'000));
        net_.at(cut, [this, who] { power_cut(who, 20'000'000); });
      }
    }
  }
  if (d.power_cut_all) {
    const std::int64_t at = static_cast<std::int64_t>(rng_.below(work_end));
    const std::int64_t back = 20'000'000 + static_cast<std::int64_t>(rng_.below(500'000'000));
    net_.at(at, [this, back] {
      note("every agent loses power at once");
      for (int i = 0; i < cfg_.agents; ++i) power_cut(i, back);
    });
  }
}

void Simulation::every(std::int64_t first, std::int64_t period, std::function<void()> fn) {
  net_.at(net_.now() + first, [this, period, fn] {
    fn();
    every(period, period, fn);
  });
}

void Simulation::flush(int i) {
  Agent& a = agents_[i];
  if (!a.up || a.failing || !a.store) return;
  (void)a.store->sync();
  after_write(i);
}

void Simulation::compact(int i) {
  Agent& a = agents_[i];
  if (!a.up || a.failing || !a.store) return;
  const std::uint64_t before = a.store->stats().compactions;
  if (Status s = a.store->compact(); !s.ok()) {
    ++result_.compactions_failed;
    note("agent" + std::to_string(i) + ": store: " + s.error().message);
  }
  result_.compactions += a.store->stats().compactions - before;
  after_write(i);
}

// A write tore (the power failed during it): the host goes down now.
void Simulation::after_write(int i) {
  if (agents_[i].disk.torn && agents_[i].up) power_cut(i, 20'000'000);
}

// The host of agent i loses power: the process dies with what its store had not written.
void Simulation::power_cut(int i, std::int64_t back_after_ns) {
  if (!agents_[i].up) return;
  ++result_.power_cuts;
  crash(i);
  restart_later(i, back_after_ns);
}

}  // namespace quiver::sim
