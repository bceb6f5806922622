// The replication protocol over Cyclone DDS: the C API wrapped once, one topic and QoS per message kind, the
// loopback configuration by default, and DDS Security's plugins when credentials are given.
#include "quiver/agents/transport/dds/dds_transport.h"

#include <dds/dds.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "dds_log.h"
#include "samples.h"
#include "quiver/base/stage_marks.h"

namespace quiver::agents::inline transport {
namespace {

// ------------------------------------------------------------------ the C API, wrapped once

/// The one place DDS return codes become quiver errors.
Error dds_error(const std::string& what, dds_return_t rc) {
  return make_error(rc == DDS_RETCODE_TIMEOUT ? ErrorCode::kTimeout : ErrorCode::kTransport,
                    what + ": " + dds_strretcode(rc));
}

/// Owns one DDS entity; deleting it deletes its children.
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t h) : h_(h) {}
  Entity(Entity&& o) noexcept : h_(o.h_) { o.h_ = 0; }
  Entity& operator=(Entity&& o) noexcept {
    reset();
    h_ = o.h_;
    o.h_ = 0;
    return *this;
  }
  ~Entity() { reset(); }
  dds_entity_t get() const { return h_; }
  void reset() {
    if (h_ > 0) dds_delete(h_);
    h_ = 0;
  }

 private:
  dds_entity_t h_ = 0;
};

/// Owns a dds_qos_t.
struct Qos {
  dds_qos_t* q = dds_create_qos();
  ~Qos() { dds_delete_qos(q); }
  Qos() = default;
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
};

// Domains shared by several transports of one process (unless each asks for its own instance).
struct SharedDomain {
  dds_entity_t handle = 0;
  int users = 0;
  std::string xml;  // the configuration it was created with
  bool secured = false;  // Cyclone has loaded the security plugins in it
};
std::mutex g_domains_mu;
std::map<dds_domainid_t, SharedDomain> g_domains;
std::atomic<dds_domainid_t> g_next_private{0x4000};
// Local ids (0..230) of private instances with DDS Security, under g_domains_mu.
std::set<dds_domainid_t> g_secured_private;
constexpr dds_domainid_t kMaxDomainId = 230;
// The role byte of a participant's card (its user data; take_new_peers()).
constexpr unsigned kCardObserver = 1, kCardSecured = 2, kCardGateway = 4;

// A sample addressed to another replica never enters this participant's reader: Cyclone drops it
// on its receive thread, so the owner thread does not wake for the beats, pulls and state chunks
// peers address to each other (DDS delivers every sample of a topic to every reader of it).
template <typename T>
bool addressed_here(const void* sample, void* self) {
  const quiver_wire_Replica& to = static_cast<const T*>(sample)->destination;
  const PeerId& me = *static_cast<const PeerId*>(self);
  return (to.agent == 0 && to.incarnation == 0) || (to.agent == me.agent && to.incarnation == me.incarnation);
}

// Takes every sample `reader` holds, in loans of up to 64, handing each to handle(sample, info).
// @returns how many were taken.
template <typename F>
std::uint64_t take_each(dds_entity_t reader, F&& handle) {
  constexpr int kMax = 64;
  void* samples[kMax];
  dds_sample_info_t infos[kMax];
  std::uint64_t taken = 0;
  for (;;) {
    for (auto& s : samples) s = nullptr;
    const dds_return_t n = dds_take(reader, samples, infos, kMax, kMax);
    if (n <= 0) return taken;
    taken += static_cast<std::uint64_t>(n);
    for (int i = 0; i < n; ++i) handle(samples[i], infos[i]);
    dds_return_loan(reader, samples, n);
    if (n < kMax) return taken;
  }
}

const char* const kPlugins[][2] = {
    // property prefix, library: init and finalize are the plugins' standard entry points
    {"dds.sec.auth.library.", "dds_security_auth"},
    {"dds.sec.crypto.library.", "dds_security_crypto"},
    {"dds.sec.access.library.", "dds_security_ac"},
};
const char* const kPluginInit[][2] = {{"init_authentication", "finalize_authentication"},
                                      {"init_crypto", "finalize_crypto"},
                                      {"init_access_control", "finalize_access_control"}};


}  // namespace

/// The participant QoS properties that make Cyclone load its security plugins with `f`.
Status set_security_qos(dds_qos_t* q, const security::DdsSecurityFiles& f) {
  const std::string dir = dds_security_plugin_dir();
  if (dir.empty())
    return make_error(ErrorCode::kNotFound,
                      "DdsTransport: DDS Security needs Cyclone's security plugins, and this build found none: set "
                      "QUIVER_DDS_SECURITY_LIB_DIR to the folder of libdds_security_auth.so");
  for (int i = 0; i < 3; ++i) {
    const std::string prefix = kPlugins[i][0];
    const std::string lib = dir + "/lib" + kPlugins[i][1] + ".so";
    if (std::FILE* probe = std::fopen(lib.c_str(), "rb")) {
      std::fclose(probe);
    } else {
      return make_error(ErrorCode::kNotFound, "DdsTransport: DDS Security plugin " + lib +
                                                  " is missing (QUIVER_DDS_SECURITY_LIB_DIR names another folder)");
    }
    dds_qset_prop(q, (prefix + "path").c_str(), lib.c_str());
    dds_qset_prop(q, (prefix + "init").c_str(), kPluginInit[i][0]);
    dds_qset_prop(q, (prefix + "finalize").c_str(), kPluginInit[i][1]);
  }
  const std::pair<const char*, const std::string*> files[] = {
      {"dds.sec.auth.identity_ca", &f.identity_ca},
      {"dds.sec.auth.identity_certificate", &f.identity_certificate},
      {"dds.sec.auth.private_key", &f.private_key},
      {"dds.sec.access.permissions_ca", &f.permissions_ca},
      {"dds.sec.access.governance", &f.governance},
      {"dds.sec.access.permissions", &f.permissions},
  };
  for (const auto& p : files) {
    if (p.second->empty())
      return make_error(ErrorCode::kInvalidArgument, std::string("DdsTransport: DdsConfig::security: ") + p.first +
                                                         " has no file");
    dds_qset_prop(q, p.first, ("file:" + *p.second).c_str());
  }
  if (!f.crl.empty()) dds_qset_prop(q, "org.eclipse.cyclonedds.sec.auth.crl", ("file:" + f.crl).c_str());
  return {};
}

std::string dds_security_plugin_dir() {
  if (const char* env = std::getenv("QUIVER_DDS_SECURITY_LIB_DIR"); env != nullptr && *env != '\0') return env;
#ifdef QUIVER_DDS_SECURITY_DIR
  return QUIVER_DDS_SECURITY_DIR;
#else
  return "";
#endif
}

// ------------------------------------------------------------------ transport

struct DdsTransport::Impl {
  std::mutex send_mu;  // send() may come from a keeper thread too (DdsReplica::keep_alive())
  PeerId self;  // the topic filters' argument: lives as long as the topics
  dds_domainid_t domain_id = 0;
  bool shared_domain = false;
  bool secured_private = false;  // domain_id is in g_secured_private
  bool secured = false;          // the participant runs DDS Security
  bool report_senders = false;  // the governance authenticates origins: deltas get Sample::sender
  std::unordered_map<dds_instance_handle_t, std::array<std::uint8_t, 16>> senders;  // by writer
  Entity private_domain;
  Entity participant;
  // One topic, writer and reader per message kind, indexed by Kind.
  enum Kind { kSummary, kDelta, kPull, kState, kBye, kKinds };
  Entity topics[kKinds];
  Entity reader_topics[kKinds];  // filtered (addressed_here) topic entities of the readers
  Entity writers[kKinds];
  Entity readers[kKinds];
  Entity participants;  // the built-in participant topic (whose user data is a replica id)
  Entity waitset;
  Entity guard;
  std::uint32_t matched_seen = 0;
  // Entities the last wait() saw triggered (their attach args); drain() takes only from these.
  std::vector<dds_attach_t> triggered;
  bool all_triggered = true;  // before the first wait (or after a timeout): take from all
  wire::SampleBuilder builder;

  // The GUID of the participant of writer `writer`, which `reader` matched (all zero when Cyclone
  // no longer knows it). Publication handles are never reused, so they are looked up once.
  std::array<std::uint8_t, 16> sender_of(dds_entity_t reader, dds_instance_handle_t writer) {
    if (auto it = senders.find(writer); it != senders.end()) return it->second;
    std::array<std::uint8_t, 16> key{};
    if (dds_builtintopic_endpoint_t* ep = dds_get_matched_publication_data(reader, writer)) {
      static_assert(sizeof ep->participant_key.v == 16);
      std::memcpy(key.data(), ep->participant_key.v, key.size());
      dds_builtintopic_free_endpoint(ep);
      if (senders.size() >= 4096) senders.clear();  // writers come and go: bounded
      senders.emplace(writer, key);
    }
    return key;
  }

  ~Impl() {
    // Children first, then the participant; a shared domain is released when its last user goes.
    waitset.reset();
    guard.reset();
    participant.reset();
    private_domain.reset();
    if (secured_private) {
      std::lock_guard<std::mutex> lock(g_domains_mu);
      g_secured_private.erase(domain_id);
    }
    if (shared_domain) {
      std::lock_guard<std::mutex> lock(g_domains_mu);
      auto it = g_domains.find(domain_id);
      if (it != g_domains.end() && --it->second.users == 0) {
        if (it->second.handle > 0) dds_delete(it->second.handle);
        g_domains.erase(it);
      }
    }
  }
};

Result<std::unique_ptr<DdsTransport>> DdsTransport::create(const PeerId& self, const DdsConfig& cfg) {
  std::unique_ptr<DdsTransport> t(new DdsTransport());
  t->self_ = self;
  t->impl_ = std::make_unique<Impl>();
  Impl& d = *t->impl_;
  d.self = self;
  d.secured = cfg.security.has_value();
  d.report_senders = d.secured && cfg.security->origin_authentication;

  std::string xml;
  switch (cfg.source) {
    case DdsConfig::Source::kLoopback: xml = loopback_config_xml(cfg); break;
    case DdsConfig::Source::kXml: xml = cfg.xml; break;
    case DdsConfig::Source::kEnvironment: {
      const char* env = std::getenv("CYCLONEDDS_URI");
      xml = env ? env : "";
      break;
    }
  }
  if (cfg.own_domain_instance && !cfg.security) {
    d.domain_id = g_next_private++;
    dds_entity_t dom = dds_create_domain(d.domain_id, xml.c_str());
    if (dom < 0) return dds_error("DdsTransport: dds_create_domain(private instance)", dom);
    d.private_domain = Entity(dom);
  } else if (cfg.own_domain_instance) {
    // Cyclone 0.10's access control looks the instance's local domain id up in the governance,
    // whose ids end at 230, so a secured private instance takes a free local id in 0..230: the
    // domain's own if it is free in this process, else the highest free one. On the wire its
    // domain is still cfg.domain (ExternalDomainId).
    std::lock_guard<std::mutex> lock(g_domains_mu);
    dds_entity_t dom = DDS_RETCODE_OUT_OF_RESOURCES;
    for (dds_domainid_t i = 0; i <= kMaxDomainId + 1; ++i) {
      const dds_domainid_t id = i == 0 ? cfg.domain : kMaxDomainId + 1 - i;
      if (id > kMaxDomainId || g_domains.count(id) > 0 || g_secured_private.count(id) > 0) continue;
      dom = dds_create_domain(id, xml.c_str());
      if (dom == DDS_RETCODE_PRECONDITION_NOT_MET) continue;  // open, but not through us
      if (dom < 0) break;
      d.domain_id = id;
      g_secured_private.insert(id);
      d.secured_private = true;
      break;
    }
    if (dom < 0) return dds_error("DdsTransport: dds_create_domain(secured private instance)", dom);
    d.private_domain = Entity(dom);
  } else {
    d.domain_id = cfg.domain;
    std::lock_guard<std::mutex> lock(g_domains_mu);
    if (g_secured_private.count(d.domain_id) > 0)
      return make_error(ErrorCode::kInvalidArgument,
                        "DdsTransport: the local id of DDS domain " + std::to_string(cfg.domain) +
                            " is taken in this process by a secured private Cyclone instance (own_domain_instance); "
                            "open this transport with own_domain_instance too");
    auto& shared = g_domains[d.domain_id];
    if (shared.users > 0 && shared.xml != xml)
      return make_error(ErrorCode::kInvalidArgument,
                        "DdsTransport: DDS domain " + std::to_string(cfg.domain) +
                            " is already open in this process with another configuration; one process shares one "
                            "configuration per domain (set DdsConfig::own_domain_instance for a private one)");
    // Cyclone loads the security plugins per domain instance, and then refuses a participant
    // without credentials in it (and an instance without them would refuse none).
    if (shared.users > 0 && shared.secured != cfg.security.has_value())
      return make_error(ErrorCode::kInvalidArgument,
                        "DdsTransport: DDS domain " + std::to_string(cfg.domain) + " is already open in this process " +
                            (shared.secured ? "with" : "without") + " DDS Security; a secured and an unsecured " +
                            "participant need separate Cyclone instances (set DdsConfig::own_domain_instance)");
    if (shared.users == 0) {
      shared.xml = xml;
      shared.secured = cfg.security.has_value();
      dds_entity_t dom = dds_create_domain(d.domain_id, xml.c_str());
      if (dom < 0 && dom != DDS_RETCODE_PRECONDITION_NOT_MET) {
        g_domains.erase(d.domain_id);
        return dds_error("DdsTransport: dds_create_domain(" + std::to_string(cfg.domain) + ")", dom);
      }
      shared.handle = dom > 0 ? dom : 0;
    }
    ++shared.users;
    d.shared_domain = true;
  }

  // User data: the replica id, a role byte (1: observer, 2: secured, 4: gateway) and the name
  // (take_new_peers()).
  std::vector<unsigned char> card(sizeof self + 1 + cfg.name.size());
  std::memcpy(card.data(), &self, sizeof self);
  card[sizeof self] = static_cast<unsigned char>((cfg.observer ? kCardObserver : 0) | (cfg.security ? kCardSecured : 0) |
                                                    (cfg.gateway ? kCardGateway : 0));
  std::memcpy(card.data() + sizeof self + 1, cfg.name.data(), cfg.name.size());
  Qos pqos;
  dds_qset_userdata(pqos.q, card.data(), card.size());
  dds_entity_t pp = 0;
  if (cfg.security) {
    if (Status s = set_security_qos(pqos.q, *cfg.security); !s.ok()) return s.error();
    // Cyclone says why it refuses credentials only in its log: the error quotes it.
    LogCapture capture;
    pp = dds_create_participant(d.domain_id, pqos.q, nullptr);
    if (pp < 0) {
      const std::string why = capture.take();
      return make_error(ErrorCode::kRefused, "DdsTransport: Cyclone DDS refused the secured participant of " +
                                                 cfg.security->identity_certificate + " (" + dds_strretcode(pp) +
                                                 ")" + (why.empty() ? "" : ": " + why));
    }
  } else {
    pp = dds_create_participant(d.domain_id, pqos.q, nullptr);
    if (pp < 0) return dds_error("DdsTransport: dds_create_participant", pp);
  }
  d.participant = Entity(pp);

  // Heartbeats and gossip beats: best effort (the protocol sends newer ones and repeats what it
  // asks for), so a beat costs one packet per reader and no acknowledgement traffic. The writer
  // keeps the latest per sender; a reader keeps a few, since beats addressed to this replica
  // (an answer, then a ping) may follow each other closely.
  Qos summary;
  dds_qset_reliability(summary.q, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(summary.q, DDS_HISTORY_KEEP_LAST, 1);
  dds_qset_ignorelocal(summary.q, DDS_IGNORELOCAL_PARTICIPANT);
  Qos summary_reader;
  dds_qset_reliability(summary_reader.q, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(summary_reader.q, DDS_HISTORY_KEEP_LAST, 8);
  dds_qset_ignorelocal(summary_reader.q, DDS_IGNORELOCAL_PARTICIPANT);
  // Everything else must arrive or be recovered by the protocol.
  Qos reliable;
  dds_qset_reliability(reliable.q, DDS_RELIABILITY_RELIABLE, cfg.max_blocking_ns);
  dds_qset_history(reliable.q, DDS_HISTORY_KEEP_ALL, 0);
  dds_qset_resource_limits(reliable.q, 100000, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  dds_qset_ignorelocal(reliable.q, DDS_IGNORELOCAL_PARTICIPANT);
  Qos best_effort;
  dds_qset_reliability(best_effort.q, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(best_effort.q, DDS_HISTORY_KEEP_LAST, 1024);
  dds_qset_ignorelocal(best_effort.q, DDS_IGNORELOCAL_PARTICIPANT);

  for (int i = 0; i < Impl::kKinds; ++i) {
    const auto topic = static_cast<DdsTopic>(i);
    const std::string what = std::string("(") + topic_name(topic) + ")";
    dds_entity_t tp = dds_create_topic(pp, &wire::descriptor(topic), topic_name(topic), nullptr, nullptr);
    if (tp < 0) return dds_error("DdsTransport: dds_create_topic" + what, tp);
    d.topics[i] = Entity(tp);
    dds_topic_filter_arg_fn filter = nullptr;
    switch (i) {
      case Impl::kSummary: filter = addressed_here<quiver_wire_Summary>; break;
      case Impl::kDelta: filter = addressed_here<quiver_wire_Delta>; break;
      case Impl::kPull: filter = addressed_here<quiver_wire_Pull>; break;
      case Impl::kState: filter = addressed_here<quiver_wire_StateChunk>; break;
      default: break;
    }
    const Qos& q = i == Impl::kSummary ? summary : reliable;
    dds_entity_t w = dds_create_writer(pp, tp, q.q, nullptr);
    if (w < 0) return dds_error("DdsTransport: dds_create_writer" + what, w);
    d.writers[i] = Entity(w);
    if (i == Impl::kDelta && !cfg.read_deltas) continue;
    const Qos& rq = i == Impl::kSummary ? summary_reader : cfg.best_effort_reader ? best_effort : q;
    // The reader gets a topic entity of its own: Cyclone applies a topic's filter to writes too.
    dds_entity_t rtp = tp;
    if (filter != nullptr) {
      rtp = dds_create_topic(pp, &wire::descriptor(topic), topic_name(topic), nullptr, nullptr);
      if (rtp < 0) return dds_error("DdsTransport: dds_create_topic" + what, rtp);
      d.reader_topics[i] = Entity(rtp);
      dds_set_topic_filter_and_arg(rtp, filter, &d.self);
    }
    dds_entity_t r = dds_create_reader(pp, rtp, rq.q, nullptr);
    if (r < 0) return dds_error("DdsTransport: dds_create_reader" + what, r);
    d.readers[i] = Entity(r);
  }

  dds_entity_t prd = dds_create_reader(pp, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr);
  if (prd < 0) return dds_error("DdsTransport: dds_create_reader(DCPSParticipant)", prd);
  d.participants = Entity(prd);

  dds_entity_t ws = dds_create_waitset(pp);
  if (ws < 0) return dds_error("DdsTransport: dds_create_waitset", ws);
  d.waitset = Entity(ws);
  dds_entity_t gc = dds_create_guardcondition(pp);
  if (gc < 0) return dds_error("DdsTransport: dds_create_guardcondition", gc);
  d.guard = Entity(gc);
  dds_return_t rc = dds_waitset_attach(ws, gc, 0);
  if (rc < 0) return dds_error("DdsTransport: dds_waitset_attach(guard)", rc);
  for (Entity* r = d.readers; r != d.readers + Impl::kKinds; ++r) {
    if (r->get() == 0) continue;  // a topic this participant does not read
    // Data available, or (for summaries) an instance state change.
    rc = dds_set_status_mask(r->get(), DDS_DATA_AVAILABLE_STATUS);
    if (rc < 0) return dds_error("DdsTransport: dds_set_status_mask", rc);
    rc = dds_waitset_attach(ws, r->get(), r->get());
    if (rc < 0) return dds_error("DdsTransport: dds_waitset_attach(reader)", rc);
  }
  rc = dds_set_status_mask(d.writers[Impl::kSummary].get(), DDS_PUBLICATION_MATCHED_STATUS);
  if (rc < 0) return dds_error("DdsTransport: dds_set_status_mask(writer)", rc);
  rc = dds_waitset_attach(ws, d.writers[Impl::kSummary].get(), d.writers[Impl::kSummary].get());
  if (rc < 0) return dds_error("DdsTransport: dds_waitset_attach(writer)", rc);
  return t;
}

DdsTransport::~DdsTransport() = default;

void DdsTransport::send(const Sample& s) {
  Impl& d = *impl_;
  std::lock_guard<std::mutex> lock(d.send_mu);
  auto [topic, sample] = d.builder.build(s.message, self_, s.to);
  dds_return_t rc = dds_write(d.writers[static_cast<int>(topic)].get(), sample);
  if (topic == DdsTopic::kDelta) stage_marks::mark(stage_marks::Stage::kWritten);
  if (rc == DDS_RETCODE_OK) ++stats_.samples_written;
  else if (rc == DDS_RETCODE_TIMEOUT) ++stats_.write_timeouts;  // the protocol recovers it
  else ++stats_.write_errors;
}

void DdsTransport::wait(std::int64_t timeout_ns) {
  Impl& d = *impl_;
  d.triggered.resize(8);
  dds_return_t n = dds_waitset_wait(d.waitset.get(), d.triggered.data(), d.triggered.size(), timeout_ns < 0 ? 0 : timeout_ns);
  if (n < 0 || n > static_cast<dds_return_t>(d.triggered.size())) {
    d.all_triggered = true;
    d.triggered.clear();
  } else {
    d.all_triggered = false;
    d.triggered.resize(static_cast<std::size_t>(n));
  }
  if (n > 0) stage_marks::mark(stage_marks::Stage::kWoken);
}

void DdsTransport::wake() { dds_set_guardcondition(impl_->guard.get(), true); }

bool DdsTransport::take_new_match() {
  dds_publication_matched_status_t st;
  if (dds_get_publication_matched_status(impl_->writers[Impl::kSummary].get(), &st) < 0)
    return false;
  bool fresh = st.total_count != impl_->matched_seen;
  impl_->matched_seen = st.total_count;
  return fresh;
}

std::vector<PeerCard> DdsTransport::take_new_peers() {
  std::vector<PeerCard> out;
  take_each(impl_->participants.get(), [&](void* sample, const dds_sample_info_t& info) {
    if (!info.valid_data || info.instance_state != DDS_IST_ALIVE) return;
    const auto* p = static_cast<const dds_builtintopic_participant_t*>(sample);
    void* data = nullptr;
    std::size_t size = 0;
    // Untrusted: anything but a replica id, a role byte and a name of bounded length (another
    // DDS application's participant, or a malformed one) is not a peer.
    constexpr std::size_t kHead = sizeof(PeerId) + 1, kMaxName = 1024;
    if (p->qos != nullptr && dds_qget_userdata(p->qos, &data, &size) && data != nullptr && size >= kHead &&
        size <= kHead + kMaxName) {
      const auto* bytes = static_cast<const unsigned char*>(data);
      PeerCard card;
      std::memcpy(&card.id, bytes, sizeof card.id);
      const unsigned role = bytes[sizeof(PeerId)];
      card.observer = (role & kCardObserver) != 0;
      card.gateway = (role & kCardGateway) != 0;
      card.name.assign(reinterpret_cast<const char*>(bytes) + kHead, size - kHead);
      // A secured participant and an unsecured one exchange no sample: not peers of each other.
      const bool secured = (role & kCardSecured) != 0;
      if (!(card.id == self_) && !card.id.is_null() && role <= (kCardObserver | kCardSecured | kCardGateway) &&
          secured == impl_->secured)
        out.push_back(std::move(card));
    }
    dds_free(data);
  });
  return out;
}

Status DdsTransport::set_deafmute(bool deaf, bool mute, std::int64_t reset_after_ns) {
  dds_return_t rc = dds_domain_set_deafmute(impl_->participant.get(), deaf, mute,
                                            reset_after_ns < 0 ? DDS_INFINITY : reset_after_ns);
  if (rc < 0) return dds_error("DdsTransport::set_deafmute", rc);
  return {};
}

void DdsTransport::dispose_self() {
  quiver_wire_Summary key{};
  key.sender_agent = self_.agent;
  key.sender_incarnation = self_.incarnation;
  dds_dispose(impl_->writers[Impl::kSummary].get(), &key);
}

void DdsTransport::drain(const std::function<void(const Sample&)>& on_sample,
                         const std::function<void(const PeerId&, bool)>& on_lost) {
  Impl& d = *impl_;
  bool triggered = false;
  dds_read_guardcondition(d.guard.get(), &triggered);
  if (triggered) dds_set_guardcondition(d.guard.get(), false);
  const PeerId self = self_;
  auto for_us = [&](const PeerId& to) { return to.is_null() || to == self; };

  auto take_all = [&](const Entity& r, auto&& handle) {
    if (r.get() == 0) return;
    if (!d.all_triggered &&
        std::find(d.triggered.begin(), d.triggered.end(), static_cast<dds_attach_t>(r.get())) == d.triggered.end())
      return;
    stats_.samples_taken += take_each(r.get(), handle);
  };

  take_all(d.readers[Impl::kSummary], [&](void* p, const dds_sample_info_t& info) {
    const auto* s = static_cast<const quiver_wire_Summary*>(p);
    if (!info.valid_data) {
      if (info.instance_state != DDS_IST_ALIVE) {
        quiver_wire_Summary key{};
        if (dds_instance_get_key(d.readers[Impl::kSummary].get(), info.instance_handle, &key) ==
            DDS_RETCODE_OK) {
          PeerId lost{key.sender_agent, key.sender_incarnation};
          dds_sample_free(&key, &quiver_wire_Summary_desc, DDS_FREE_CONTENTS);
          if (!(lost == self)) {
            ++stats_.peers_lost;
            on_lost(lost, info.instance_state == DDS_IST_NOT_ALIVE_DISPOSED);
          }
        }
      }
      return;
    }
    on_sample(wire::sample_of(*s));
  });
  // The other topics: samples addressed to someone else are skipped.
  auto take_topic = [&](Impl::Kind kind) {
    take_all(d.readers[kind], [&](void* p, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      Sample e = wire::sample_of(static_cast<DdsTopic>(kind), p);
      if (kind == Impl::kDelta) stage_marks::mark(stage_marks::Stage::kTaken);
      if (kind == Impl::kDelta && d.report_senders)
        e.sender = d.sender_of(d.readers[kind].get(), info.publication_handle);
      if (for_us(e.to)) on_sample(e);
    });
  };
  take_topic(Impl::kDelta);
  take_topic(Impl::kPull);
  take_topic(Impl::kState);
  take_topic(Impl::kBye);
  d.all_triggered = true;  // until the next wait() says otherwise
}

}  // namespace quiver::agents
