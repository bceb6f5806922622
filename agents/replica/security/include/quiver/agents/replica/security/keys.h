#pragma once
/// @file
/// The credentials of a Quiver deployment under DDS Security (docs/security.md), as PEM files in
/// one directory:
///
///     DIR/ca.key.pem          the CA's private key (EC P-256): keep it off the robots
///     DIR/ca.pem              the CA certificate (CN=Quiver CA): identity and permissions CA
///     DIR/governance.xml      what the domains protect (readable copy)
///     DIR/governance.p7s      the same, S/MIME signed by the CA (what Cyclone reads)
///     DIR/crl.pem             the certificates the CA has revoked
///     DIR/agents/NAME/key.pem          the agent's private key (EC P-256)
///     DIR/agents/NAME/cert.pem         its certificate, subject CN=NAME,O=Quiver
///     DIR/agents/NAME/permissions.xml  what it may publish and read (readable copy)
///     DIR/agents/NAME/permissions.p7s  the same, S/MIME signed by the CA
///
/// Certificates are about the wall clock (validity, revocation): these functions read it, unlike
/// the rest of Quiver, whose time is injected.
///
/// Threading: none of these functions keeps state; two processes must not change one DIR at once.

#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::inline replica::security {

struct KeyOptions {
  double ca_valid_days = 7300;  ///< the CA certificate's lifetime (20 years)
};

struct AgentKeyOptions {
  double valid_days = 3650;  ///< notAfter = notBefore + valid_days
  double backdate_days = 0;  ///< notBefore = now - backdate_days (tests: an expired certificate)
};

/// Creates the CA and the domain-wide documents in `dir` (created if missing): ca.key.pem,
/// ca.pem, governance.xml, governance.p7s, crl.pem (empty).
/// @returns kAlreadyExists (naming the file) when `dir` already holds a CA: it is never
/// overwritten (every agent certificate it signed would lose its trust); kIo when a file cannot
/// be written; kInternal when OpenSSL fails.
Status init_keys(const std::string& dir, const KeyOptions& options = {});

/// Creates DIR/agents/NAME/{key.pem, cert.pem, permissions.xml, permissions.p7s}: a key, a
/// certificate signed by the CA (subject CN=NAME,O=Quiver, a random 127-bit serial), and
/// permissions (signed by the CA) to publish and subscribe to every topic on domains 0..230 for
/// the certificate's validity, everything else denied.
/// @returns kInvalidArgument for a name that is not [A-Za-z0-9_.-]{1,64} or a non-positive
/// validity; kNotFound when DIR holds no CA (run init_keys); kAlreadyExists when the agent has
/// credentials already (revoke them and choose another name, or delete the folder).
Status add_agent(const std::string& dir, const std::string& name,
                 const AgentKeyOptions& options = {});

/// Adds the certificate of agent `name` to DIR/crl.pem (re-signed by the CA). Revoking an agent
/// twice is not an error. Peers that load the new CRL refuse the agent.
/// @returns kNotFound when the CA, the CRL or the agent's certificate is missing.
Status revoke_agent(const std::string& dir, const std::string& name);

/// Absolute paths of the files a secured DDS participant needs (empty `crl`: none).
struct DdsSecurityFiles {
  std::string identity_ca;           ///< DIR/ca.pem
  std::string identity_certificate;  ///< DIR/agents/NAME/cert.pem
  std::string private_key;           ///< DIR/agents/NAME/key.pem
  std::string permissions_ca;        ///< DIR/ca.pem
  std::string governance;            ///< DIR/governance.p7s
  std::string permissions;           ///< DIR/agents/NAME/permissions.p7s
  std::string crl;                   ///< DIR/crl.pem
  /// The governance gives every topic's metadata origin authentication
  /// (`*_WITH_ORIGIN_AUTHENTICATION`): another member cannot send samples under this agent's
  /// participant, so a transport may report who sent a sample (Sample::sender) for the fast path.
  bool origin_authentication = false;
};

/// Whether the governance in `governance_p7s` (S/MIME, checked against the CA in `ca_pem`) gives
/// every topic rule's metadata origin authentication.
/// @returns false when some rule does not; kNotFound / kMalformed / kRefused when the file cannot
/// be read, does not parse, or was not signed by that CA.
Result<bool> governance_authenticates_origins(const std::string& governance_p7s, const std::string& ca_pem);

/// The credentials of agent `name` in `dir`, checked now: every file exists, the certificate was
/// signed by the CA, is not revoked by DIR/crl.pem and is within its validity.
/// @returns kNotFound ("no credentials for agent NAME in DIR: run `quiver keys add-agent NAME
/// --dir DIR`"), kRefused ("agent NAME's certificate expired on ...", "... was revoked", "... is
/// not signed by ..."), kInvalidArgument for a bad name, kMalformed for an unreadable PEM file.
Result<DdsSecurityFiles> agent_files(const std::string& dir, const std::string& name);

/// One agent's credentials, as `quiver keys list` shows them.
struct AgentInfo {
  std::string name;        ///< the folder's name (and the certificate's CN)
  std::string serial;      ///< the certificate's serial, hex
  std::string not_before;  ///< "2026-11-23 10:00:00 UTC"
  std::string not_after;
  bool revoked = false;
  bool expired = false;  ///< its notAfter has passed
  bool valid = false;    ///< signed by the CA, not revoked, within its validity now
  std::string problem;   ///< why not valid (empty when valid)
};

/// Every agent under DIR/agents, by name.
/// @returns kNotFound when DIR holds no CA.
Result<std::vector<AgentInfo>> list_agents(const std::string& dir);

/// True for a name that add_agent accepts: [A-Za-z0-9_.-]{1,64}, and not "." or "..".
bool is_valid_agent_name(const std::string& name);

}  // namespace quiver::agents::inline replica::security
