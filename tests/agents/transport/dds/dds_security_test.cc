// Secured Cyclone DDS participants (DdsConfig::security) on the loopback interface: agents with
// credentials from one CA replicate; a participant without security, one whose certificate
// expired and one whose certificate was revoked exchange nothing with them. Every negative case
// has a positive control beside it. Each test has its own DDS domain id, and each replica its own
// Cyclone instance (own_domain_instance), as separate processes would.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>

#include "forged_delta.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/runtime/process/security_setup.h"
#include "quiver/agents/replica/security/identity.h"
#include "quiver/agents/replica/security/keys.h"
#include "quiver/base/hash.h"

namespace quiver::agents {
namespace {

namespace fs = std::filesystem;
using security::DdsSecurityFiles;

constexpr std::int64_t kMs = 1'000'000;

class DdsSecurityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "quiver-dds-sec-XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
    ASSERT_TRUE(security::init_keys(dir_).ok());
  }
  void TearDown() override { fs::remove_all(dir_); }

  DdsSecurityFiles files(const std::string& name) {
    auto f = security::agent_files(dir_, name);
    EXPECT_TRUE(f.ok()) << f.error().to_string();
    return f.ok() ? *f : DdsSecurityFiles{};
  }
  /// The files of `name` as they are, unchecked: what a misconfigured or hostile agent would use.
  DdsSecurityFiles raw_files(const std::string& name, const std::string& crl_dir = "") {
    const fs::path d = fs::absolute(dir_);
    DdsSecurityFiles f;
    f.identity_ca = f.permissions_ca = (d / "ca.pem").string();
    f.identity_certificate = (d / "agents" / name / "cert.pem").string();
    f.private_key = (d / "agents" / name / "key.pem").string();
    f.governance = (d / "governance.p7s").string();
    f.permissions = (d / "agents" / name / "permissions.p7s").string();
    f.crl = ((crl_dir.empty() ? d : fs::path(crl_dir)) / "crl.pem").string();
    return f;
  }

  static Result<std::unique_ptr<DdsReplica>> replica(const std::string& name, std::uint32_t domain,
                                                     std::optional<DdsSecurityFiles> sec,
                                                     bool own = true) {
    DdsReplicaOptions o;
    o.name = name;
    o.dds.domain = domain;
    o.dds.own_domain_instance = own;
    o.dds.security = std::move(sec);
    o.replicator.heartbeat_ns = 50 * kMs;
    return DdsReplica::create(o);
  }
  /// The options of agent `name` on `domain`, made secure by enable_security() from dir_ (DDS
  /// Security, signed deltas, dir_/policy.json when there is one).
  DdsReplicaOptions secured(const std::string& name, std::uint32_t domain) {
    DdsReplicaOptions o;
    o.name = name;
    o.dds.domain = domain;
    o.dds.own_domain_instance = true;
    o.replicator.heartbeat_ns = 50 * kMs;
    Status s = enable_security(o, dir_);
    EXPECT_TRUE(s.ok()) << s.error().to_string();
    return o;
  }
  static std::unique_ptr<DdsReplica> must(Result<std::unique_ptr<DdsReplica>> r) {
    EXPECT_TRUE(r.ok()) << r.error().to_string();
    return r.ok() ? std::move(*r) : nullptr;
  }

  // Spins every replica in turn (all on this thread) until `done` or `timeout_ms`.
  template <class F>
  static bool spin_until(const std::vector<DdsReplica*>& rs, F done, std::int64_t timeout_ms) {
    const std::int64_t end = monotonic_ns() + timeout_ms * kMs;
    while (monotonic_ns() < end) {
      for (DdsReplica* r : rs) r->spin_once(2 * kMs);
      if (done()) return true;
    }
    return false;
  }
  static void commit_node(DdsReplica& r, const std::string& name) {
    auto tx = r.graph().begin();
    ASSERT_TRUE(tx.create_node("thing", name).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  static bool has(DdsReplica& r, const std::string& node) {
    return r.graph().find_node(node).has_value();
  }

  std::string dir_;
};

TEST_F(DdsSecurityTest, SecuredAgentsReplicateAndAnUnsecuredParticipantIsShutOut) {
  constexpr std::uint32_t kDomain = 171;
  ASSERT_TRUE(security::add_agent(dir_, "a").ok());
  ASSERT_TRUE(security::add_agent(dir_, "b").ok());
  auto a = must(replica("a", kDomain, files("a")));
  auto b = must(replica("b", kDomain, files("b")));
  auto u = must(replica("u", kDomain, std::nullopt));
  auto v = must(replica("v", kDomain, std::nullopt));
  ASSERT_TRUE(a && b && u && v);
  std::vector<DdsReplica*> all{a.get(), b.get(), u.get(), v.get()};

  commit_node(*a, "from_a");
  commit_node(*u, "from_u");
  // Positive controls: the secured pair replicates, and so does the unsecured pair.
  EXPECT_TRUE(spin_until(
      all, [&] { return has(*b, "from_a") && has(*v, "from_u"); }, 20'000));
  commit_node(*b, "from_b");
  commit_node(*v, "from_v");
  EXPECT_TRUE(spin_until(
      all, [&] { return has(*a, "from_b") && has(*u, "from_v"); }, 20'000));
  // Then a while longer: nothing crosses between the secured and the unsecured.
  spin_until(
      all, [] { return false; }, 2'000);
  for (const char* n : {"from_a", "from_b"}) {
    EXPECT_FALSE(has(*u, n)) << n;
    EXPECT_FALSE(has(*v, n)) << n;
  }
  for (const char* n : {"from_u", "from_v"}) {
    EXPECT_FALSE(has(*a, n)) << n;
    EXPECT_FALSE(has(*b, n)) << n;
  }
  EXPECT_EQ(a->replicator().live_peer_count(), 1u);
  EXPECT_EQ(u->replicator().live_peer_count(), 1u);
}

TEST_F(DdsSecurityTest, ExpiredAndRevokedCertificatesAreRefusedAtCreate) {
  constexpr std::uint32_t kDomain = 172;
  ASSERT_TRUE(security::add_agent(dir_, "a").ok());
  ASSERT_TRUE(security::add_agent(dir_, "c").ok());
  security::AgentKeyOptions expired;
  expired.backdate_days = 2;
  expired.valid_days = 1;
  ASSERT_TRUE(security::add_agent(dir_, "old", expired).ok());
  ASSERT_TRUE(security::add_agent(dir_, "gone").ok());
  ASSERT_TRUE(security::revoke_agent(dir_, "gone").ok());

  auto old = replica("old", kDomain, raw_files("old"));
  ASSERT_FALSE(old.ok());
  EXPECT_EQ(old.error().code, ErrorCode::kRefused);
  std::printf("expired: %s\n", old.error().message.c_str());
  auto gone = replica("gone", kDomain, raw_files("gone"));
  ASSERT_FALSE(gone.ok());
  EXPECT_EQ(gone.error().code, ErrorCode::kRefused);
  std::printf("revoked: %s\n", gone.error().message.c_str());

  // Positive control: valid credentials of the same CA, same directory, same domain.
  auto a = must(replica("a", kDomain, files("a")));
  auto c = must(replica("c", kDomain, raw_files("c")));
  ASSERT_TRUE(a && c);
  commit_node(*a, "from_a");
  EXPECT_TRUE(spin_until(
      {a.get(), c.get()}, [&] { return has(*c, "from_a"); }, 20'000));
}

TEST_F(DdsSecurityTest, PeersRefuseARevokedAgentThatKeptAnOldCrl) {
  for (const char* n : {"a", "b", "r", "s"}) ASSERT_TRUE(security::add_agent(dir_, n).ok());
  // r keeps the CRL of before its revocation: its own plugins accept its certificate.
  const std::string stale = dir_ + "/stale";
  fs::create_directories(stale);
  fs::copy_file(dir_ + "/crl.pem", stale + "/crl.pem");
  ASSERT_TRUE(security::revoke_agent(dir_, "r").ok());

  {
    // Positive control, on a domain of its own: r's credentials work with a peer (s) that has
    // not heard of the revocation either.
    constexpr std::uint32_t kControlDomain = 176;
    auto r = must(replica("r", kControlDomain, raw_files("r", stale)));
    auto s = must(replica("s", kControlDomain, raw_files("s", stale)));
    ASSERT_TRUE(r && s);
    commit_node(*r, "from_r");
    EXPECT_TRUE(spin_until(
        {r.get(), s.get()}, [&] { return has(*s, "from_r"); }, 20'000));
  }

  constexpr std::uint32_t kDomain = 173;
  std::mutex mu;
  int revoked_lines = 0;
  route_dds_log([&](const std::string& line) {
    std::lock_guard<std::mutex> lock(mu);
    revoked_lines += line.find("certificate revoked") != std::string::npos;
  });
  struct Unroute {
    ~Unroute() { route_dds_log(nullptr); }
  } unroute;
  auto a = must(replica("a", kDomain, files("a")));
  auto b = must(replica("b", kDomain, files("b")));
  auto r = must(replica("r", kDomain, raw_files("r", stale)));
  ASSERT_TRUE(a && b && r);
  std::vector<DdsReplica*> all{a.get(), b.get(), r.get()};
  commit_node(*a, "from_a");
  commit_node(*r, "from_r");
  // Positive control: a and b, with the current CRL, replicate.
  EXPECT_TRUE(spin_until(
      all, [&] { return has(*b, "from_a"); }, 20'000));
  spin_until(
      all, [] { return false; }, 2'000);
  EXPECT_FALSE(has(*a, "from_r"));
  EXPECT_FALSE(has(*b, "from_r"));
  EXPECT_FALSE(has(*r, "from_a"));
  EXPECT_EQ(r->replicator().live_peer_count(), 0u);
  // And it is the revocation that stopped the handshakes.
  std::lock_guard<std::mutex> lock(mu);
  EXPECT_GT(revoked_lines, 0);
}

TEST_F(DdsSecurityTest, TwoIdentitiesShareOneDomainInstance) {
  constexpr std::uint32_t kDomain = 174;
  ASSERT_TRUE(security::add_agent(dir_, "a").ok());
  ASSERT_TRUE(security::add_agent(dir_, "b").ok());
  auto a = must(replica("a", kDomain, files("a"), /*own=*/false));
  auto b = must(replica("b", kDomain, files("b"), /*own=*/false));
  ASSERT_TRUE(a && b);
  commit_node(*a, "from_a");
  EXPECT_TRUE(spin_until(
      {a.get(), b.get()}, [&] { return has(*b, "from_a"); }, 20'000));
}

TEST_F(DdsSecurityTest, SecuredAndUnsecuredNeedSeparateInstances) {
  constexpr std::uint32_t kDomain = 175;
  ASSERT_TRUE(security::add_agent(dir_, "a").ok());
  auto a = must(replica("a", kDomain, files("a"), /*own=*/false));
  ASSERT_TRUE(a);
  // Cyclone would refuse it with a bare "Error" (its plugins are loaded in the instance).
  auto u = replica("u", kDomain, std::nullopt, /*own=*/false);
  ASSERT_FALSE(u.ok());
  EXPECT_EQ(u.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(u.error().message.find("own_domain_instance"), std::string::npos) << u.error().message;
  // Positive control: the same participant in its own instance.
  auto own = must(replica("u", kDomain, std::nullopt, /*own=*/true));
  EXPECT_TRUE(own);
}


// Graph-level permissions over secured DDS (enable_security): every delta is signed by its
// origin and checked by every receiver against DIR/policy.json. An authenticated agent whose own
// commit check is off (a modified agent) writes what the policy reserves to another: both honest
// replicas refuse it and stay equal; its allowed write (the control) reaches them. An agent that
// does not sign its deltas is refused as well.
TEST_F(DdsSecurityTest, AnAuthenticatedAgentWritingOutsideItsPermissionsIsRefusedByEveryReplica) {
  for (const char* n : {"speech", "panel", "intruder", "unsigned"}) ASSERT_TRUE(security::add_agent(dir_, n).ok());
  {
    std::FILE* f = std::fopen((fs::path(dir_) / "policy.json").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(R"({"default": "allow", "rules": [{"action": "write", "target": "speaking", "agents": ["speech"]}]})", f);
    std::fclose(f);
  }
  auto make = [&](const std::string& name) { return secured(name, 193); };
  auto speech = must(DdsReplica::create(make("speech")));
  auto panel = must(DdsReplica::create(make("panel")));
  auto intruder = must(DdsReplica::create(make("intruder")));
  DdsReplicaOptions uo = make("unsigned");
  uo.permissions = std::make_shared<permissions::PolicyAdmission>(permissions::Policy::allow_all(), nullptr, nullptr);
  auto unsigned_agent = must(DdsReplica::create(uo));
  ASSERT_TRUE(speech && panel && intruder && unsigned_agent);
  std::vector<Error> errors;
  panel->replicator().on_error([&](const Error& e) { errors.push_back(e); });
  intruder->graph().set_permission_check(nullptr);  // its own check is off
  std::vector<DdsReplica*> all = {speech.get(), panel.get(), intruder.get(), unsigned_agent.get()};
  ASSERT_TRUE(spin_until(all, [&] { return panel->replicator().live_peer_count() == 3; }, 15000));

  graph::NodeId robot;
  {
    auto tx = speech->graph().begin();
    robot = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.set(robot, "speaking", graph::Value(false)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_TRUE(spin_until(all, [&] {
    return intruder->graph().has_node(robot) && panel->graph().has_node(robot) && unsigned_agent->graph().has_node(robot);
  }, 10000));
  {
    auto tx = intruder->graph().begin();
    ASSERT_TRUE(tx.set(robot, "battery", graph::Value(0.5)).ok());  // allowed: the control
    ASSERT_TRUE(tx.commit().ok());
    // A signed replica sends the commits of one round as one delta (one signature): a round
    // apart, the two commits travel, and are judged, apart.
    intruder->spin_once(0);
    auto tx2 = intruder->graph().begin();
    ASSERT_TRUE(tx2.set(robot, "speaking", graph::Value(true)).ok());  // reserved to speech
    ASSERT_TRUE(tx2.commit().ok());
    auto tx3 = unsigned_agent->graph().begin();
    ASSERT_TRUE(tx3.set(robot, "unsigned_note", graph::Value("hi")).ok());
    ASSERT_TRUE(tx3.commit().ok());
  }
  ASSERT_TRUE(spin_until(all, [&] {
    return panel->replicator().stats().deltas_refused >= 2 && speech->replicator().stats().deltas_refused >= 2 &&
           panel->graph().attr(robot, "battery") != nullptr && speech->graph().attr(robot, "battery") != nullptr;
  }, 15000)) << "refused at panel " << panel->replicator().stats().deltas_refused << ", at speech "
             << speech->replicator().stats().deltas_refused;
  spin_until(all, [] { return false; }, 500);
  for (DdsReplica* r : {speech.get(), panel.get()}) {
    EXPECT_EQ(*r->graph().get<bool>(robot, "speaking"), false);
    EXPECT_EQ(r->graph().attr(robot, "unsigned_note"), nullptr);
  }
  EXPECT_EQ(*intruder->graph().get<bool>(robot, "speaking"), true) << "the intruder keeps its own change";
  EXPECT_EQ(speech->graph().digest(), panel->graph().digest());
  bool named = false, unsigned_named = false;
  for (const Error& e : errors) {
    named = named || (e.code == ErrorCode::kPermissionDenied &&
                      e.message.find("agent 'intruder' may not write 'speaking' on 'robot'") != std::string::npos);
    unsigned_named = unsigned_named || e.message.find("not signed") != std::string::npos;
  }
  EXPECT_TRUE(named);
  EXPECT_TRUE(unsigned_named);
  // Speech's own write of the attribute is admitted everywhere.
  {
    auto tx = speech->graph().begin();
    ASSERT_TRUE(tx.set(robot, "speaking", graph::Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_TRUE(spin_until(all, [&] { return *panel->graph().get<bool>(robot, "speaking"); }, 10000));
  // The local check: panel may not write it either.
  auto tx = panel->graph().begin();
  ASSERT_TRUE(tx.set(robot, "speaking", graph::Value(false)).ok());
  auto c = tx.commit();
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().code, ErrorCode::kPermissionDenied);
}


// The fast path (docs/security.md): a delta that its origin's own participant sent is admitted on
// that participant's authenticated identity, without verifying the signature. A member that sends
// a delta under another member's name (signed with its own key, as a member can) comes from its
// own participant: the signature is verified, and every replica refuses the forgery.
TEST_F(DdsSecurityTest, ADeltaFromItsOriginIsAdmittedOnItsSenderAndAMembersForgeryIsVerifiedAndRefused) {
  for (const char* n : {"a", "b", "forger"}) ASSERT_TRUE(security::add_agent(dir_, n).ok());
  constexpr std::uint32_t kDomain = 188;
  DdsReplicaOptions ao = secured("a", kDomain), bo = secured("b", kDomain);
  ASSERT_TRUE(ao.dds.security && ao.dds.security->origin_authentication) << "a new governance authenticates origins";
  auto a = must(DdsReplica::create(ao));
  auto b = must(DdsReplica::create(bo));
  // The forger: a member with credentials of its own, writing samples by hand.
  DdsConfig fc;
  fc.domain = kDomain;
  fc.own_domain_instance = true;
  fc.name = "forger";
  fc.security = files("forger");
  auto forger = DdsTransport::create(PeerId{fnv1a64("forger"), 1}, fc);
  ASSERT_TRUE(forger.ok()) << forger.error().to_string();
  ASSERT_TRUE(a && b);
  std::vector<std::string> errors;
  b->replicator().on_error([&](const Error& e) { errors.push_back(e.message); });
  std::vector<DdsReplica*> ab{a.get(), b.get()};
  auto spin = [&](auto done, std::int64_t ms) {
    return spin_until(ab, [&] {
      (*forger)->drain([](const Sample&) {}, [](const PeerId&, bool) {});
      return done();
    }, ms);
  };

  // The control: a's own deltas reach b straight from a's participant, and b admits them on it
  // (once they know each other: before, b would get a's change in the state it joins with).
  ASSERT_TRUE(spin([&] { return a->replicator().live_peer_count() >= 1 && b->replicator().live_peer_count() >= 1; },
                   15000));
  spin([] { return false; }, 300);
  commit_node(*a, "from_a");
  ASSERT_TRUE(spin([&] { return has(*b, "from_a"); }, 15000));
  EXPECT_GE(bo.permissions->admitted_on_sender(), 1u);
  EXPECT_EQ(bo.permissions->signatures_verified(), 0u) << "nothing reached b but from its origin";

  // The forgery: a node under a's name and numbers far beyond a's, signed with the forger's key.
  const PeerId victim = a->id();
  auto signer = security::Signer::load(dir_, "forger");
  ASSERT_TRUE(signer.ok());
  auto payload = testing::bytes_of(
      testing::forged_node_delta(victim, 1000, 1000, graph::Dot{victim, 9'000'000}, "thing", "forged"));
  auto sig = std::make_shared<const std::vector<std::uint8_t>>(signer->sign(*payload));
  const Sample forged{victim, PeerId{}, DeltaMsg{victim, 1000, 1000, payload, sig}};
  const std::uint64_t verified_before = bo.permissions->signatures_verified();
  // Sent until b has judged it (the forger's writer may match b's reader after the first one).
  ASSERT_TRUE(spin([&] {
    (*forger)->send(forged);
    return b->replicator().stats().deltas_refused >= 1 && a->replicator().stats().deltas_refused >= 1;
  }, 15000)) << "refused at b: " << b->replicator().stats().deltas_refused
             << ", at a: " << a->replicator().stats().deltas_refused;
  EXPECT_GT(bo.permissions->signatures_verified(), verified_before) << "the forgery was verified, not taken on its sender";
  EXPECT_FALSE(has(*b, "forged"));
  EXPECT_FALSE(has(*a, "forged"));
  bool named = false;
  for (const std::string& e : errors) named = named || e.find("its signature does not hold") != std::string::npos;
  EXPECT_TRUE(named);
  // And a's next change is still admitted on its sender at b.
  const std::uint64_t on_sender = bo.permissions->admitted_on_sender();
  commit_node(*a, "after");
  ASSERT_TRUE(spin([&] { return has(*b, "after"); }, 10000));
  EXPECT_GT(bo.permissions->admitted_on_sender(), on_sender);
  EXPECT_EQ(a->graph().digest(), b->graph().digest());
}


// A certificate that expires while its participant runs: Cyclone drops the participant when the
// certificate's validity ends. Before, its changes reach its peer; after, they no longer do,
// while a valid agent's change (the control) still does.
TEST_F(DdsSecurityTest, AnAgentWhoseCertificateExpiresWhileRunningIsDropped) {
  ASSERT_TRUE(security::add_agent(dir_, "a").ok());
  ASSERT_TRUE(security::add_agent(dir_, "c").ok());
  security::AgentKeyOptions brief;
  brief.valid_days = 15.0 / 86400.0;  // 15 s: room for a slow handshake on a loaded machine
  ASSERT_TRUE(security::add_agent(dir_, "b", brief).ok());
  const std::int64_t start = monotonic_ns();
  auto a = must(replica("a", 194, files("a")));
  auto b = must(replica("b", 194, files("b")));
  auto c = must(replica("c", 194, files("c")));
  ASSERT_TRUE(a && b && c);
  std::vector<DdsReplica*> all = {a.get(), b.get(), c.get()};
  commit_node(*b, "before_expiry");
  ASSERT_TRUE(spin_until(all, [&] { return has(*a, "before_expiry"); }, 12000)) << "b's change arrives while valid";
  // Past the end of b's validity (and a margin for Cyclone's timer).
  const std::int64_t left_ms = 15000 - (monotonic_ns() - start) / kMs + 2000;
  if (left_ms > 0) spin_until(all, [] { return false; }, left_ms);
  commit_node(*b, "after_expiry");
  commit_node(*c, "control");
  ASSERT_TRUE(spin_until(all, [&] { return has(*a, "control"); }, 6000)) << "a valid agent still reaches a";
  spin_until(all, [] { return false; }, 1500);
  EXPECT_FALSE(has(*a, "after_expiry")) << "the expired agent's change does not reach a";
}

}  // namespace
}  // namespace quiver::agents
