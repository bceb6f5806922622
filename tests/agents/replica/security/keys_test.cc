// quiver::security: the CA and agent credentials (cross-checked with the `openssl` program), and
// the signatures agents put on graph-level payloads.

#include "quiver/agents/replica/security/keys.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "quiver/agents/replica/security/identity.h"
#include "quiver/base/hash.h"

namespace quiver::agents::security {
namespace {

namespace fs = std::filesystem;

class KeysTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "quiver-keys-XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& rel) const { return (fs::path(dir_) / rel).string(); }
  // Runs a shell command (the openssl program: a cross-check only); its exit status and output.
  static std::pair<int, std::string> run(const std::string& cmd) {
    std::string out;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (p == nullptr) return {-1, ""};
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
  }
  static std::string read(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  std::string dir_;
};

std::vector<std::uint8_t> bytes(const std::string& s) { return {s.begin(), s.end()}; }

TEST_F(KeysTest, InitAndAddAgentMakeFilesThatOpensslAccepts) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "planner", {}).ok());
  for (const char* f : {"ca.key.pem", "ca.pem", "governance.xml", "governance.p7s", "crl.pem",
                        "agents/planner/key.pem", "agents/planner/cert.pem",
                        "agents/planner/permissions.xml", "agents/planner/permissions.p7s"})
    EXPECT_TRUE(fs::exists(path(f))) << f;
  // Private keys are the owner's alone.
  for (const char* f : {"ca.key.pem", "agents/planner/key.pem"})
    EXPECT_EQ(fs::status(path(f)).permissions() & (fs::perms::group_all | fs::perms::others_all),
              fs::perms::none)
        << f;

  auto [rc, out] = run("openssl verify -CAfile " + path("ca.pem") + " -CRLfile " + path("crl.pem") +
                       " -crl_check " + path("agents/planner/cert.pem"));
  EXPECT_EQ(rc, 0) << out;
  std::tie(rc, out) =
      run("openssl x509 -noout -subject -nameopt RFC2253 -in " + path("agents/planner/cert.pem"));
  EXPECT_EQ(out, "subject=CN=planner,O=Quiver\n");
  std::tie(rc, out) = run("openssl x509 -noout -text -in " + path("ca.pem"));
  EXPECT_NE(out.find("CA:TRUE"), std::string::npos) << out;
  EXPECT_NE(out.find("Certificate Sign, CRL Sign"), std::string::npos) << out;
  EXPECT_NE(out.find("Quiver CA"), std::string::npos) << out;
  EXPECT_NE(out.find("prime256v1"), std::string::npos) << out;
  for (const char* doc : {"governance", "agents/planner/permissions"}) {
    std::tie(rc, out) = run("openssl smime -verify -in " + path(std::string(doc) + ".p7s") +
                            " -CAfile " + path("ca.pem") + " -text");
    EXPECT_EQ(rc, 0) << doc << ": " << out;
    // What the signature covers is the readable copy (S/MIME text has CRLF line ends).
    std::erase(out, '\r');
    EXPECT_NE(out.find(read(path(std::string(doc) + ".xml"))), std::string::npos)
        << doc << ": " << out;
  }
  const std::string gov = read(path("governance.xml"));
  for (const char* s :
       {"<domains><id_range><min>0</min><max>230</max></id_range></domains>",
        "<allow_unauthenticated_participants>false", "<enable_join_access_control>true",
        "<discovery_protection_kind>ENCRYPT", "<liveliness_protection_kind>ENCRYPT",
        "<rtps_protection_kind>SIGN", "<topic_expression>*</topic_expression>",
        "<enable_read_access_control>true", "<enable_write_access_control>true",
        "<metadata_protection_kind>ENCRYPT", "<data_protection_kind>ENCRYPT"})
    EXPECT_NE(gov.find(s), std::string::npos) << s;
  const std::string perm = read(path("agents/planner/permissions.xml"));
  EXPECT_NE(perm.find("<subject_name>CN=planner,O=Quiver</subject_name>"), std::string::npos)
      << perm;
  EXPECT_NE(perm.find("<default>DENY</default>"), std::string::npos) << perm;
  // A tampered document no longer verifies (the signature is not decoration).
  std::string p7s = read(path("governance.p7s"));
  const auto at = p7s.find("ENCRYPT</data_protection_kind>");
  ASSERT_NE(at, std::string::npos);
  p7s.replace(at, 7, "NONE   ");
  std::ofstream(path("tampered.p7s")) << p7s;
  std::tie(rc, out) = run("openssl smime -verify -in " + path("tampered.p7s") + " -CAfile " +
                          path("ca.pem") + " -out /dev/null");
  EXPECT_NE(rc, 0) << out;
}

// The fast path of the admission needs a governance that authenticates origins: a new one does, a
// document of the older form (metadata ENCRYPT) signed by the same CA does not, and one the CA did
// not sign is an error, not a "no".
TEST_F(KeysTest, TheGovernanceSaysWhetherItAuthenticatesOrigins) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "planner", {}).ok());
  auto now = governance_authenticates_origins(path("governance.p7s"), path("ca.pem"));
  ASSERT_TRUE(now.ok()) << now.error().to_string();
  EXPECT_TRUE(*now);
  auto files = agent_files(dir_, "planner");
  ASSERT_TRUE(files.ok()) << files.error().to_string();
  EXPECT_TRUE(files->origin_authentication);

  std::string older = read(path("governance.xml"));
  const std::string kind = "ENCRYPT_WITH_ORIGIN_AUTHENTICATION</metadata_protection_kind>";
  const auto at = older.find(kind);
  ASSERT_NE(at, std::string::npos) << older;
  older.replace(at, kind.size(), "ENCRYPT</metadata_protection_kind>");
  std::ofstream(path("older.xml")) << older;
  auto [rc, out] = run("openssl smime -sign -text -in " + path("older.xml") + " -signer " + path("ca.pem") +
                       " -inkey " + path("ca.key.pem") + " -out " + path("older.p7s"));
  ASSERT_EQ(rc, 0) << out;
  auto before = governance_authenticates_origins(path("older.p7s"), path("ca.pem"));
  ASSERT_TRUE(before.ok()) << before.error().to_string();
  EXPECT_FALSE(*before);

  // Signed by another CA: refused, naming the file.
  const std::string other = path("other");
  ASSERT_TRUE(init_keys(other, {}).ok());
  auto foreign = governance_authenticates_origins(path("governance.p7s"), other + "/ca.pem");
  ASSERT_FALSE(foreign.ok());
  EXPECT_EQ(foreign.error().code, ErrorCode::kRefused);
  EXPECT_NE(foreign.error().message.find("governance.p7s"), std::string::npos) << foreign.error().message;
}

TEST_F(KeysTest, SerialsDiffer) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "a", {}).ok());
  ASSERT_TRUE(add_agent(dir_, "b", {}).ok());
  auto list = list_agents(dir_);
  ASSERT_TRUE(list.ok()) << list.error().to_string();
  ASSERT_EQ(list->size(), 2u);
  EXPECT_NE((*list)[0].serial, (*list)[1].serial);
  EXPECT_GE((*list)[0].serial.size(), 30u);  // ~127 random bits
}

TEST_F(KeysTest, InitRefusesToOverwriteACa) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  const std::string before = read(path("ca.pem"));
  Status again = init_keys(dir_, {});
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
  EXPECT_NE(again.error().message.find(path("ca.pem")), std::string::npos) << again.error().message;
  EXPECT_EQ(read(path("ca.pem")), before);
}

TEST_F(KeysTest, AddAgentChecksNamesTheCaAndDuplicates) {
  Status no_ca = add_agent(dir_, "a", {});
  ASSERT_FALSE(no_ca.ok());
  EXPECT_EQ(no_ca.error().code, ErrorCode::kNotFound);
  EXPECT_NE(no_ca.error().message.find("quiver keys init"), std::string::npos)
      << no_ca.error().message;
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  for (const std::string& bad : std::vector<std::string>{"", "a b", "../x", "a/b", "..", "é",
                                                         std::string(65, 'x'), "CN=x,O=y"}) {
    Status s = add_agent(dir_, bad, {});
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument) << bad;
  }
  EXPECT_TRUE(add_agent(dir_, std::string(64, 'x'), {}).ok());
  EXPECT_TRUE(add_agent(dir_, "Agent_1.v-2", {}).ok());
  Status twice = add_agent(dir_, "Agent_1.v-2", {});
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.error().code, ErrorCode::kAlreadyExists);
  AgentKeyOptions zero;
  zero.valid_days = 0;
  EXPECT_EQ(add_agent(dir_, "z", zero).error().code, ErrorCode::kInvalidArgument);
}

TEST_F(KeysTest, AgentFilesSayWhyCredentialsAreRefused) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "good", {}).ok());
  AgentKeyOptions expired;
  expired.backdate_days = 2;
  expired.valid_days = 1;
  ASSERT_TRUE(add_agent(dir_, "old", expired).ok());
  ASSERT_TRUE(add_agent(dir_, "gone", {}).ok());
  ASSERT_TRUE(agent_files(dir_, "gone").ok());  // valid until revoked
  ASSERT_TRUE(revoke_agent(dir_, "gone").ok());
  ASSERT_TRUE(revoke_agent(dir_, "gone").ok());  // twice is fine

  auto good = agent_files(dir_, "good");
  ASSERT_TRUE(good.ok()) << good.error().to_string();
  EXPECT_TRUE(fs::path(good->identity_certificate).is_absolute());
  EXPECT_EQ(good->identity_ca, fs::absolute(path("ca.pem")).string());
  EXPECT_EQ(good->permissions_ca, good->identity_ca);
  EXPECT_EQ(good->crl, fs::absolute(path("crl.pem")).string());
  EXPECT_EQ(good->permissions, fs::absolute(path("agents/good/permissions.p7s")).string());

  auto old = agent_files(dir_, "old");
  ASSERT_FALSE(old.ok());
  EXPECT_EQ(old.error().code, ErrorCode::kRefused);
  EXPECT_NE(old.error().message.find("agent old's certificate expired on "), std::string::npos)
      << old.error().message;

  auto gone = agent_files(dir_, "gone");
  ASSERT_FALSE(gone.ok());
  EXPECT_EQ(gone.error().code, ErrorCode::kRefused);
  EXPECT_NE(gone.error().message.find("was revoked"), std::string::npos) << gone.error().message;
  // The openssl program reads our CRL the same way.
  auto [rc, out] = run("openssl verify -CAfile " + path("ca.pem") + " -CRLfile " + path("crl.pem") +
                       " -crl_check " + path("agents/gone/cert.pem"));
  EXPECT_NE(rc, 0);
  EXPECT_NE(out.find("revoked"), std::string::npos) << out;

  auto none = agent_files(dir_, "nobody");
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(none.error().message, "no credentials for agent nobody in " + dir_ +
                                      ": run `quiver keys add-agent nobody --dir " + dir_ + "`");

  // A certificate from another CA does not pass for one of ours.
  const std::string other = path("other");
  ASSERT_TRUE(init_keys(other, {}).ok());
  ASSERT_TRUE(add_agent(other, "good", {}).ok());
  fs::copy_file(other + "/agents/good/cert.pem", path("agents/good/cert.pem"),
                fs::copy_options::overwrite_existing);
  auto foreign = agent_files(dir_, "good");
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.error().message.find("not signed by this CA"), std::string::npos)
      << foreign.error().message;

  auto list = list_agents(dir_);
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 3u);
  EXPECT_EQ((*list)[0].name, "gone");
  EXPECT_TRUE((*list)[0].revoked);
  EXPECT_FALSE((*list)[0].valid);
  EXPECT_FALSE((*list)[1].valid);  // good: now with the other CA's certificate
  EXPECT_EQ((*list)[2].name, "old");
  EXPECT_FALSE((*list)[2].revoked);
  EXPECT_TRUE((*list)[2].expired);
  EXPECT_NE((*list)[2].problem.find("expired"), std::string::npos);
}

// Signer::prepare() computes a signature's nonce ahead (the costly part): a signature made with a
// prepared nonce and one made without verify alike, and no nonce serves twice (a second signature
// of the same bytes differs, whether a nonce was prepared between them or not).
TEST_F(KeysTest, SignaturesWithANoncePreparedAheadVerifyAndNeverShareIt) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "a", {}).ok());
  auto a = Signer::load(dir_, "a");
  ASSERT_TRUE(a.ok()) << a.error().to_string();
  auto book = IdentityBook::load(dir_);
  ASSERT_TRUE(book.ok());
  const auto data = bytes("delta: node 42 attr pose = (1, 2, 3)");
  const auto prepared_at_load = a->sign(data);
  const auto computed_now = a->sign(data);  // nothing prepared since the last one
  a->prepare();
  a->prepare();  // a second call keeps the one ready
  const auto prepared = a->sign(data);
  const auto after = a->sign(data);
  std::set<std::vector<std::uint8_t>> distinct;
  for (const auto* sig : {&prepared_at_load, &computed_now, &prepared, &after}) {
    EXPECT_TRUE(book->verify(fnv1a64("a"), data, *sig).ok());
    EXPECT_LE(sig->size(), 72u);
    distinct.insert(*sig);
  }
  EXPECT_EQ(distinct.size(), 4u) << "a nonce served twice";
  // The openssl program agrees (a cross-check of the DER form).
  std::ofstream(path("data.bin"), std::ios::binary).write(reinterpret_cast<const char*>(data.data()), data.size());
  std::ofstream(path("sig.der"), std::ios::binary)
      .write(reinterpret_cast<const char*>(prepared.data()), static_cast<std::streamsize>(prepared.size()));
  auto [rc, out] = run("openssl x509 -in " + path("agents/a/cert.pem") + " -pubkey -noout > " + path("pub.pem") +
                       " && openssl dgst -sha256 -verify " + path("pub.pem") + " -signature " + path("sig.der") + " " +
                       path("data.bin"));
  EXPECT_EQ(rc, 0) << out;
}

TEST_F(KeysTest, SignaturesVerifyOnlyForTheSignerAndTheBytes) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "a", {}).ok());
  ASSERT_TRUE(add_agent(dir_, "b", {}).ok());
  AgentKeyOptions expired;
  expired.backdate_days = 2;
  expired.valid_days = 1;
  ASSERT_TRUE(add_agent(dir_, "old", expired).ok());
  ASSERT_TRUE(add_agent(dir_, "gone", {}).ok());
  ASSERT_TRUE(revoke_agent(dir_, "gone").ok());

  auto a = Signer::load(dir_, "a");
  ASSERT_TRUE(a.ok()) << a.error().to_string();
  EXPECT_EQ(a->name(), "a");
  auto book = IdentityBook::load(dir_);
  ASSERT_TRUE(book.ok()) << book.error().to_string();
  EXPECT_EQ(book->size(), 2u);
  EXPECT_EQ(book->name_of(fnv1a64("a")), "a");
  EXPECT_EQ(book->name_of(fnv1a64("b")), "b");

  const auto data = bytes("delta: node 42 attr pose = (1, 2, 3)");
  const auto sig = a->sign(data);
  EXPECT_LE(sig.size(), 72u);
  EXPECT_GE(sig.size(), 8u);
  EXPECT_TRUE(book->verify(fnv1a64("a"), data, sig).ok());
  // ECDSA is randomized: another signature of the same bytes, also valid.
  EXPECT_TRUE(book->verify(fnv1a64("a"), data, a->sign(data)).ok());

  for (std::size_t i : {std::size_t{0}, data.size() / 2, data.size() - 1}) {
    auto tampered = data;
    tampered[i] ^= 0x01;
    Status s = book->verify(fnv1a64("a"), tampered, sig);
    ASSERT_FALSE(s.ok()) << i;
    EXPECT_EQ(s.error().code, ErrorCode::kRefused);
    EXPECT_NE(s.error().message.find("bad signature from agent a"), std::string::npos)
        << s.error().message;
  }
  auto bad_sig = sig;
  bad_sig[bad_sig.size() / 2] ^= 0x40;
  EXPECT_FALSE(book->verify(fnv1a64("a"), data, bad_sig).ok());
  EXPECT_FALSE(book->verify(fnv1a64("a"), data, {}).ok());
  // b did not sign it.
  EXPECT_FALSE(book->verify(fnv1a64("b"), data, sig).ok());

  Status unknown = book->verify(fnv1a64("mallory"), data, sig);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, ErrorCode::kNotFound);
  EXPECT_NE(unknown.error().message.find("unknown agent"), std::string::npos);

  // Expired and revoked agents are not in the book, even with a signature made by their key.
  for (const char* name : {"old", "gone"}) {
    EXPECT_EQ(book->name_of(fnv1a64(name)), std::nullopt) << name;
    auto signer = Signer::load(dir_, name);
    ASSERT_TRUE(signer.ok());
    Status s = book->verify(fnv1a64(name), data, signer->sign(data));
    ASSERT_FALSE(s.ok()) << name;
    EXPECT_EQ(s.error().code, ErrorCode::kRefused);
    EXPECT_NE(s.error().message.find(std::string(name) == "old" ? "expired on" : "was revoked"),
              std::string::npos)
        << s.error().message;
  }

  // An agent added later is known after reload(); one revoked since is not.
  ASSERT_TRUE(add_agent(dir_, "late", {}).ok());
  auto late = Signer::load(dir_, "late");
  ASSERT_TRUE(late.ok());
  EXPECT_EQ(book->verify(fnv1a64("late"), data, late->sign(data)).error().code,
            ErrorCode::kNotFound);
  ASSERT_TRUE(revoke_agent(dir_, "b").ok());
  ASSERT_TRUE(book->reload().ok());
  EXPECT_TRUE(book->verify(fnv1a64("late"), data, late->sign(data)).ok());
  EXPECT_EQ(book->name_of(fnv1a64("b")), std::nullopt);

  EXPECT_EQ(Signer::load(dir_, "nobody").error().code, ErrorCode::kNotFound);
  EXPECT_EQ(Signer::load(dir_, "../a").error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(IdentityBook::load(path("nowhere")).error().code, ErrorCode::kNotFound);
}

// The cost of a signature and of its check (reported in docs/security.md).
TEST_F(KeysTest, SignAndVerifyCost) {
  ASSERT_TRUE(init_keys(dir_, {}).ok());
  ASSERT_TRUE(add_agent(dir_, "a", {}).ok());
  auto a = Signer::load(dir_, "a");
  auto book = IdentityBook::load(dir_);
  ASSERT_TRUE(a.ok() && book.ok());
  std::vector<std::uint8_t> data(256, 0x5a);  // a typical small delta
  constexpr int kRounds = 2000;
  std::vector<std::vector<std::uint8_t>> sigs;
  sigs.reserve(kRounds);
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  for (int i = 0; i < kRounds; ++i) {
    data[0] = static_cast<std::uint8_t>(i);
    sigs.push_back(a->sign(data));
  }
  auto t1 = Clock::now();
  int ok = 0;
  for (int i = 0; i < kRounds; ++i) {
    data[0] = static_cast<std::uint8_t>(i);
    ok += book->verify(fnv1a64("a"), data, sigs[static_cast<std::size_t>(i)]).ok();
  }
  auto t2 = Clock::now();
  EXPECT_EQ(ok, kRounds);
  // With the nonce prepared ahead (Signer::prepare(), outside the timed part), as a replica signs.
  double ahead_ns = 0;
  for (int i = 0; i < kRounds; ++i) {
    data[0] = static_cast<std::uint8_t>(i);
    a->prepare();
    const auto s0 = Clock::now();
    sigs[static_cast<std::size_t>(i)] = a->sign(data);
    ahead_ns += std::chrono::duration<double, std::nano>(Clock::now() - s0).count();
  }
  for (int i = 0; i < kRounds; i += 97) {
    data[0] = static_cast<std::uint8_t>(i);
    EXPECT_TRUE(book->verify(fnv1a64("a"), data, sigs[static_cast<std::size_t>(i)]).ok()) << i;
  }
  const double sign_us = std::chrono::duration<double, std::micro>(t1 - t0).count() / kRounds;
  const double verify_us = std::chrono::duration<double, std::micro>(t2 - t1).count() / kRounds;
  const double ahead_us = ahead_ns / 1000.0 / kRounds;
  std::printf(
      "[ cost     ] ECDSA P-256/SHA-256 over 256 bytes: sign %.1f us (%.2f us with the nonce prepared "
      "ahead), verify %.1f us (mean of %d)\n",
      sign_us, ahead_us, verify_us, kRounds);
  RecordProperty("sign_us", std::to_string(sign_us));
  RecordProperty("sign_prepared_us", std::to_string(ahead_us));
  RecordProperty("verify_us", std::to_string(verify_us));
}

}  // namespace
}  // namespace quiver::agents::security
