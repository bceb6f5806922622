// FrameTree's publishing: the owner's changes written to both copies of the shared table through
// the latch (chunks, name strings, key tables, slots, history blocks), what they replace retired,
// then the listeners notified.

#include <algorithm>
#include <bit>
#include <cmath>
#include <tuple>

#include "frame_keys.h"
#include "frame_owner.h"
#include "frame_store.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {

using internal::Core;
using internal::HistoryBlock;
using internal::HistSample;
using internal::KeyTable;
using internal::ld;
using internal::Node;
using internal::Sample;
using internal::SlotData;
using internal::st;
using internal::TableOp;
using internal::TableState;
using internal::hash_id;
using internal::hash_name;

namespace {

std::uint32_t pow2_at_least(std::uint64_t n) {
  return static_cast<std::uint32_t>(std::bit_ceil(std::max<std::uint64_t>(n, 16)));
}

void fill_history(HistoryBlock* h, const std::vector<Sample>& samples) {
  const std::uint32_t n = static_cast<std::uint32_t>(samples.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    HistSample& d = h->samples()[i];
    const Sample& a = samples[i];
    st(d.stamp, a.stamp);
    for (int k = 0; k < 4; ++k) st(d.X[k], a.X.q[k]);
    for (int k = 0; k < 3; ++k) st(d.X[4 + k], a.X.p[k]);
    double theta = 0, cos_theta = 1, inv_sin = 0, sign = 1, inv_dt = 0;
    if (i + 1 < n) {
      const Sample& b = samples[i + 1];
      const double dot =
          a.X.q[0] * b.X.q[0] + a.X.q[1] * b.X.q[1] + a.X.q[2] * b.X.q[2] + a.X.q[3] * b.X.q[3];
      sign = dot < 0 ? -1.0 : 1.0;
      const double ad = std::fabs(dot);
      if (ad < 1.0 - 1e-12) {  // otherwise blend linearly, as Eigen's slerp does
        theta = std::acos(ad);
        inv_sin = 1.0 / std::sin(theta);
        cos_theta = ad;
      }
      inv_dt = 1.0 / static_cast<double>(b.stamp - a.stamp);
    }
    st(d.theta, theta);
    st(d.cos_theta, cos_theta);
    st(d.inv_sin, inv_sin);
    st(d.sign, sign);
    st(d.inv_dt, inv_dt);
  }
  st(h->size, n);
}

void write_slot(SlotData* d, Node& n, int copy, std::vector<HistoryBlock*>& retire_blocks) {
  st(d->generation, n.generation);
  st(d->live, n.live ? 1u : 0u);
  st(d->parent, n.parent);
  st(d->root, n.root);
  st(d->depth, n.depth);
  st(d->version, n.version);
  st(d->id[0], n.id.dot.replica.agent);
  st(d->id[1], n.id.dot.replica.incarnation);
  st(d->id[2], n.id.dot.counter);
  d->name.store(n.pub_name, std::memory_order_release);  // the string is complete before
  for (int i = 0; i < 9; ++i) st(d->X_RN[i], n.R_RN[i]);
  for (int i = 0; i < 3; ++i) st(d->X_RN[9 + i], n.p_RN[i]);
  for (int i = 0; i < 4; ++i) st(d->X_PN[i], n.X_PN.q[i]);
  for (int i = 0; i < 3; ++i) st(d->X_PN[4 + i], n.X_PN.p[i]);
  st(d->stamp, n.stamp);
  if (n.hist_dirty) {
    HistoryBlock*& h = n.pub_hist[copy];
    const std::size_t need = n.live && n.samples.size() >= 2 ? n.samples.size() : 0;
    if (need == 0) {
      if (h) st(h->size, 0u);
    } else {
      if (h == nullptr || h->capacity < need) {
        const auto cap = static_cast<std::uint32_t>(std::max<std::size_t>(4, std::bit_ceil(need)));
        if (h) retire_blocks.push_back(h);
        h = HistoryBlock::create(cap);
      }
      fill_history(h, n.samples);
    }
    d->history.store(h, std::memory_order_release);  // a new block is complete before
  }
}

void apply_ops(KeyTable* t, const std::vector<TableOp>& ops, TableState* count) {
  for (const TableOp& op : ops) {
    std::uint32_t i = static_cast<std::uint32_t>(op.hash) & t->mask;
    if (op.insert) {
      for (;; i = (i + 1) & t->mask) {
        const std::uint64_t e = ld(t->entries[i]);
        if (e == KeyTable::kEmpty || e == KeyTable::kTomb) {
          if (e == KeyTable::kEmpty && count) ++count->used;
          st(t->entries[i], KeyTable::pack(op.hash, op.slot));
          break;
        }
      }
    } else {
      const std::uint64_t want = KeyTable::pack(op.hash, op.slot);
      for (std::uint32_t n = 0; n <= t->mask; ++n, i = (i + 1) & t->mask) {
        const std::uint64_t e = ld(t->entries[i]);
        if (e == KeyTable::kEmpty) break;
        if (e == want) {
          st(t->entries[i], KeyTable::kTomb);
          break;
        }
      }
    }
  }
}

KeyTable* build_table(std::uint32_t cap,
                      const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries) {
  auto* t = new KeyTable(cap);
  std::vector<TableOp> ops;
  ops.reserve(entries.size());
  for (const auto& [h, s] : entries) ops.push_back(TableOp{true, h, s});
  apply_ops(t, ops, nullptr);
  return t;
}

}  // namespace

void FrameTree::publish(FrameUpdate& u) {
  Owner& o = *own_;
  Core& core = *core_;
  // Chunks for new slots (published before the slots are referenced).
  const std::uint32_t need_chunks = static_cast<std::uint32_t>(
      (o.nodes.size() + internal::kChunkSlots - 1) / internal::kChunkSlots);
  while (core.chunk_count < need_chunks) {
    core.chunks[core.chunk_count].store(new internal::Chunk(), std::memory_order_release);
    ++core.chunk_count;
  }
  // Name strings: one immutable string per published name.
  std::vector<const std::string*> retire_strings;
  for (std::int32_t s : o.touched) {
    Node& n = o.nodes[s];
    const std::string_view want = n.live ? std::string_view(n.name) : std::string_view();
    const std::string* cur = n.pub_name;
    if (cur && *cur == want) continue;
    if (cur == nullptr && want.empty()) continue;
    if (cur) retire_strings.push_back(cur);
    n.pub_name = want.empty() ? nullptr : new std::string(want);
  }
  // Key tables: rebuild when due, else replay the operations on both copies.
  auto plan = [](TableState& ts) {
    std::uint32_t inserts = 0;
    for (const TableOp& op : ts.ops) inserts += op.insert ? 1 : 0;
    if (ts.rebuild || ts.capacity == 0 || 2ull * (ts.used + inserts) > ts.capacity) {
      ts.rebuild = true;
      ts.capacity = pow2_at_least(4ull * ts.live + 16);
      ts.used = ts.live;
    }
  };
  plan(o.names);
  plan(o.ids);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> name_entries, id_entries;
  if (o.names.rebuild)
    for (const auto& [name, s] : o.by_name)
      name_entries.emplace_back(hash_name(name), static_cast<std::uint32_t>(s));
  if (o.ids.rebuild)
    for (const auto& [id, s] : o.by_id)
      id_entries.emplace_back(hash_id(id), static_cast<std::uint32_t>(s));
  std::vector<KeyTable*> retire_tables;
  std::vector<HistoryBlock*> retire_blocks;

  for (int copy = 0; copy < 2; ++copy) {
    // Readers move to the other copy; from here on this copy may be modified.
    core.seq.store(core.seq.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    std::atomic_thread_fence(std::memory_order_release);
    for (auto [ts, ptr, entries] : {std::tuple{&o.names, &core.names[copy], &name_entries},
                                    std::tuple{&o.ids, &core.ids[copy], &id_entries}}) {
      if (ts->rebuild) {
        KeyTable* old = ptr->load(std::memory_order_relaxed);
        if (old) retire_tables.push_back(old);
        ptr->store(build_table(ts->capacity, *entries), std::memory_order_release);
      } else {
        apply_ops(ptr->load(std::memory_order_relaxed), ts->ops, copy == 0 ? ts : nullptr);
      }
    }
    for (std::int32_t s : o.touched)
      write_slot(core.slot(copy, static_cast<std::uint32_t>(s)), o.nodes[s], copy, retire_blocks);
  }
  core.seq.store(core.seq.load(std::memory_order_relaxed), std::memory_order_release);
  for (std::int32_t s : o.touched) {
    o.nodes[s].touched = false;
    o.nodes[s].hist_dirty = false;
  }
  o.touched.clear();
  for (TableState* ts : {&o.names, &o.ids}) {
    ts->ops.clear();
    ts->rebuild = false;
  }
  for (const std::string* p : retire_strings) core.retire(p);
  for (HistoryBlock* p : retire_blocks) core.retire(p);
  for (KeyTable* p : retire_tables) core.retire(p);
  core.reclaim();
  ++o.stats.publishes;

  u.moved = o.moved;
  u.removed = o.removed;
  o.notify(u);
  o.moved.clear();
  o.removed.clear();
}

}  // namespace quiver::kinematics
