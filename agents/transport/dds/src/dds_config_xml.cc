// The embedded Cyclone DDS configurations: loopback by default, or one interface of a robot
// team's network; unicast discovery of listed peers only, never multicast, never routed.
#include <algorithm>
#include <string>
#include <vector>

#include "quiver/agents/transport/dds/dds_transport.h"

namespace quiver::agents::inline transport {
namespace {

// One interface, no multicast, never routed, unicast discovery of the listed peers only, and no
// sample larger than the protocol sends.
std::string unicast_xml(bool loopback, const std::string& address, const std::vector<std::string>& peers,
                        int max_index, const std::string& tag, const DdsConfig& cfg) {
  auto ms = [](std::int64_t ns) { return std::to_string(std::max<std::int64_t>(1, ns / 1'000'000)) + "ms"; };
  // A lease of 5 s or more is what many processes on one host need (docs/protocol.md): Cyclone
  // then runs at their pace too, so that discovering and acknowledging a hundred peers does not
  // take more wakeups than the host has.
  const bool many = cfg.lease_ns >= kManyProcessesLeaseNs;
  std::string xml =
      "<CycloneDDS><Domain id=\"any\">"
      "<General>"
      "<Interfaces><NetworkInterface address=\"" + address + "\"/></Interfaces>"
      "<AllowMulticast>false</AllowMulticast>"
      "<DontRoute>true</DontRoute>";
  // Loopback carries 64 KiB datagrams: a discovery burst to a new peer, or a large sample, takes
  // a few packets instead of dozens.
  if (many && loopback) xml += "<MaxMessageSize>65000B</MaxMessageSize><FragmentSize>16000B</FragmentSize>";
  xml += "</General><Discovery>";
  if (!tag.empty()) xml += "<Tag>" + tag + "</Tag>";
  xml += "<ParticipantIndex>auto</ParticipantIndex>"
         "<MaxAutoParticipantIndex>" + std::to_string(max_index) + "</MaxAutoParticipantIndex><Peers>";
  for (const std::string& p : peers) xml += "<Peer address=\"" + p + "\"/>";
  xml += "</Peers><LeaseDuration>" + ms(cfg.lease_ns) + "</LeaseDuration>";
  if (cfg.own_domain_instance) xml += "<ExternalDomainId>" + std::to_string(cfg.domain) + "</ExternalDomainId>";
  // One unicast port (and socket) for discovery and data: one receive thread fewer per process.
  if (many && loopback)
    xml += "<Ports><UnicastMetaOffset>10</UnicastMetaOffset><UnicastDataOffset>10</UnicastDataOffset></Ports>";
  xml += "</Discovery>";
  // No sample larger than the largest the protocol sends (a delta at its limit): Cyclone drops a
  // bigger one before reassembling it, so a peer cannot make us allocate 2 GiB for one sample.
  xml += "<Internal><MaxSampleSize>" + std::to_string(kMaxSampleBytes) + "B</MaxSampleSize>";
  // Reliable writers' periodic heartbeats every 250 ms to 1 s instead of 20 to 100 ms: with a
  // hundred peers, those of the discovery writers alone kept both cores busy.
  if (many) xml += "<HeartbeatInterval min=\"50 ms\" minsched=\"250 ms\">1 s</HeartbeatInterval>";
  if (cfg.xmit_loss_permille > 0)
    xml += "<Test><XmitLossiness>" + std::to_string(cfg.xmit_loss_permille) + "</XmitLossiness></Test>";
  xml += "</Internal>";
  xml += "</Domain></CycloneDDS>";
  return xml;
}

}  // namespace

std::string loopback_config_xml(const DdsConfig& cfg) {
  return unicast_xml(true, "127.0.0.1", {"127.0.0.1"}, 120, "", cfg);
}

std::string network_config_xml(const NetworkDomain& net, const DdsConfig& cfg) {
  return unicast_xml(false, net.address, net.peers, net.max_participant_index, net.tag, cfg);
}

}  // namespace quiver::agents
