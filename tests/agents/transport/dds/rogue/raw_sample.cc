#include "raw_sample.h"

#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace quiver::rogue {
namespace {

// A serdata that only knows how to hand out its bytes. The transmit path asks for them padded to
// a multiple of 4, so they are stored zero-padded.
struct RawSerdata {
  ddsi_serdata c;  // first: Cyclone casts between the two
  std::uint32_t size;
  unsigned char* bytes;
};

bool eqkey(const ddsi_serdata*, const ddsi_serdata*) { return true; }  // one instance of their own
std::uint32_t get_size(const ddsi_serdata* d) { return reinterpret_cast<const RawSerdata*>(d)->size; }
ddsi_serdata* from_ser(const ddsi_sertype*, ddsi_serdata_kind, const nn_rdata*, size_t) { return nullptr; }
ddsi_serdata* from_ser_iov(const ddsi_sertype*, ddsi_serdata_kind, ddsrt_msg_iovlen_t, const ddsrt_iovec_t*,
                           size_t) {
  return nullptr;
}
ddsi_serdata* from_keyhash(const ddsi_sertype*, const ddsi_keyhash*) { return nullptr; }
ddsi_serdata* from_sample(const ddsi_sertype*, ddsi_serdata_kind, const void*) { return nullptr; }
void to_ser(const ddsi_serdata* d, size_t off, size_t sz, void* buf) {
  std::memcpy(buf, reinterpret_cast<const RawSerdata*>(d)->bytes + off, sz);
}
ddsi_serdata* to_ser_ref(const ddsi_serdata* d, size_t off, size_t sz, ddsrt_iovec_t* ref) {
  ref->iov_base = reinterpret_cast<const RawSerdata*>(d)->bytes + off;
  ref->iov_len = static_cast<ddsrt_iov_len_t>(sz);
  return ddsi_serdata_ref(d);
}
void to_ser_unref(ddsi_serdata* d, const ddsrt_iovec_t*) { ddsi_serdata_unref(d); }
bool to_sample(const ddsi_serdata*, void*, void**, void*) { return false; }
ddsi_serdata* to_untyped(const ddsi_serdata* d) { return ddsi_serdata_ref(d); }
bool untyped_to_sample(const ddsi_sertype*, const ddsi_serdata*, void*, void**, void*) { return false; }
void free_raw(ddsi_serdata* d) {
  auto* r = reinterpret_cast<RawSerdata*>(d);
  std::free(r->bytes);
  std::free(r);
}
size_t print(const ddsi_sertype*, const ddsi_serdata* d, char* buf, size_t size) {
  return static_cast<size_t>(std::snprintf(buf, size, "raw(%u bytes)", get_size(d)));
}
void get_keyhash(const ddsi_serdata*, ddsi_keyhash* buf, bool) { std::memset(buf, 0, sizeof *buf); }

const ddsi_serdata_ops* raw_ops() {
  static const ddsi_serdata_ops ops = [] {
    ddsi_serdata_ops o{};
    o.eqkey = eqkey;
    o.get_size = get_size;
    o.from_ser = from_ser;
    o.from_ser_iov = from_ser_iov;
    o.from_keyhash = from_keyhash;
    o.from_sample = from_sample;
    o.to_ser = to_ser;
    o.to_ser_ref = to_ser_ref;
    o.to_ser_unref = to_ser_unref;
    o.to_sample = to_sample;
    o.to_untyped = to_untyped;
    o.untyped_to_sample = untyped_to_sample;
    o.free = free_raw;
    o.print = print;
    o.get_keyhash = get_keyhash;
    return o;
  }();
  return &ops;
}

}  // namespace

const ddsi_sertype* probe_sertype(dds_entity_t participant, dds_entity_t topic, const void* valid_sample) {
  const char* partition[] = {"quiver-rogue-sertype-probe"};
  dds_qos_t* q = dds_create_qos();
  dds_qset_partition(q, 1, partition);
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
  dds_entity_t pub = dds_create_publisher(participant, q, nullptr);
  dds_entity_t sub = dds_create_subscriber(participant, q, nullptr);
  dds_entity_t wr = dds_create_writer(pub, topic, q, nullptr);
  dds_entity_t rd = dds_create_reader(sub, topic, q, nullptr);
  dds_delete_qos(q);
  const ddsi_sertype* type = nullptr;
  if (wr > 0 && rd > 0 && dds_write(wr, valid_sample) == DDS_RETCODE_OK) {
    ddsi_serdata* sd = nullptr;
    dds_sample_info_t info;
    for (int i = 0; i < 100 && type == nullptr; ++i) {
      if (dds_takecdr(rd, &sd, 1, &info, DDS_ANY_STATE) == 1) {
        type = sd->type;
        ddsi_serdata_unref(sd);
      } else {
        dds_sleepfor(DDS_MSECS(10));
      }
    }
  }
  if (pub > 0) dds_delete(pub);
  if (sub > 0) dds_delete(sub);
  return type;
}

dds_return_t write_raw(dds_entity_t writer, const ddsi_sertype* type, std::span<const std::uint8_t> bytes) {
  auto* r = static_cast<RawSerdata*>(std::calloc(1, sizeof(RawSerdata)));
  const std::size_t padded = (bytes.size() + 3) & ~std::size_t{3};
  r->bytes = static_cast<unsigned char*>(std::calloc(1, padded == 0 ? 4 : padded));
  if (!bytes.empty()) std::memcpy(r->bytes, bytes.data(), bytes.size());
  r->size = static_cast<std::uint32_t>(bytes.size());
  ddsi_serdata_init(&r->c, type, SDK_DATA);
  r->c.ops = raw_ops();
  r->c.hash = type->serdata_basehash;
  return dds_writecdr(writer, &r->c);  // takes the reference
}

}  // namespace quiver::rogue
