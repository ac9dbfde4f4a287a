// The Cyclone configuration a participant is given without CYCLONEDDS_URI: loopback only by
// default, named interfaces and peers on request, and names that could inject XML refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "dds/participant.hpp"

namespace df::dds {
namespace {

TEST(ParticipantConfig, DefaultIsLoopbackOnlyWithoutMulticast) {
    auto xml = domain_xml(ParticipantConfig{}, false);
    ASSERT_TRUE(xml.is_ok()) << xml.status().message();
    EXPECT_NE(xml->find("<NetworkInterface name=\"lo\"/>"), std::string::npos) << *xml;
    EXPECT_NE(xml->find("<AllowMulticast>false</AllowMulticast>"), std::string::npos) << *xml;
    EXPECT_NE(xml->find("<Peer address=\"127.0.0.1\"/>"), std::string::npos) << *xml;
    EXPECT_NE(xml->find("<MaxAutoParticipantIndex>119</MaxAutoParticipantIndex>"),
              std::string::npos);
    EXPECT_EQ(xml->find("SharedMemory"), std::string::npos);
    // Exactly one interface: nothing but loopback.
    EXPECT_EQ(xml->find("<NetworkInterface", xml->find("<NetworkInterface") + 1),
              std::string::npos);
}

TEST(ParticipantConfig, NamedInterfacesAndPeersOptIn) {
    ParticipantConfig c;
    c.interfaces = {"eth0", "eth1"};
    c.peers = {"192.0.2.10"};
    auto xml = domain_xml(c, true);
    ASSERT_TRUE(xml.is_ok()) << xml.status().message();
    EXPECT_NE(xml->find("<NetworkInterface name=\"eth0\"/><NetworkInterface name=\"eth1\"/>"),
              std::string::npos);
    EXPECT_EQ(xml->find("name=\"lo\""), std::string::npos);
    EXPECT_NE(xml->find("<Peer address=\"192.0.2.10\"/>"), std::string::npos);
    EXPECT_EQ(xml->find("127.0.0.1"), std::string::npos);
    EXPECT_NE(xml->find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
    EXPECT_NE(xml->find("<SharedMemory><Enable>true</Enable>"), std::string::npos);
}

TEST(ParticipantConfig, InterfacesWithoutPeersDiscoverByMulticast) {
    ParticipantConfig c;
    c.interfaces = {"eth0"};
    auto xml = domain_xml(c, false);
    ASSERT_TRUE(xml.is_ok());
    EXPECT_EQ(xml->find("AllowMulticast"), std::string::npos) << *xml;
    EXPECT_EQ(xml->find("<Peers>"), std::string::npos) << *xml;
}

TEST(ParticipantConfig, NamesThatCouldInjectXmlAreRefusedNamingTheField) {
    ParticipantConfig c;
    c.interfaces = {"eth0\"/><AllowMulticast>true</AllowMulticast><x a=\""};
    auto bad_if = domain_xml(c, false);
    ASSERT_FALSE(bad_if.is_ok());
    EXPECT_NE(bad_if.status().message().find("dds.interfaces"), std::string::npos)
        << bad_if.status().message();
    ParticipantConfig p;
    p.peers = {"10.0.0.1 <"};
    auto bad_peer = domain_xml(p, false);
    ASSERT_FALSE(bad_peer.is_ok());
    EXPECT_NE(bad_peer.status().message().find("dds.peers"), std::string::npos);
    ParticipantConfig e;
    e.peers = {""};
    EXPECT_FALSE(domain_xml(e, false).is_ok());
    ParticipantConfig m;
    m.max_participants_per_host = 0;
    auto bad_max = domain_xml(m, false);
    ASSERT_FALSE(bad_max.is_ok());
    EXPECT_NE(bad_max.status().message().find("[1, 1000]"), std::string::npos);
}

TEST(ParticipantConfig, LeaseIsTwoSecondsUnlessExtraXmlSetsOne) {
    auto xml = domain_xml(ParticipantConfig{}, false);
    ASSERT_TRUE(xml.is_ok());
    EXPECT_NE(xml->find("<Discovery><LeaseDuration>2000ms</LeaseDuration>"), std::string::npos)
        << *xml;
    ParticipantConfig c;
    c.interfaces = {"eth0"};  // no peers: the lease still applies
    auto multicast = domain_xml(c, false);
    ASSERT_TRUE(multicast.is_ok());
    EXPECT_NE(multicast->find("<LeaseDuration>2000ms</LeaseDuration>"), std::string::npos);
    ParticipantConfig own;
    own.extra_xml = "<Discovery><LeaseDuration>1s</LeaseDuration></Discovery>";
    auto theirs = domain_xml(own, false);
    ASSERT_TRUE(theirs.is_ok());
    EXPECT_EQ(theirs->find("2000ms"), std::string::npos) << *theirs;
    ParticipantConfig bad;
    bad.lease_ms = -1;
    auto refused = domain_xml(bad, false);
    ASSERT_FALSE(refused.is_ok());
    EXPECT_NE(refused.status().message().find("[0, 3600000]"), std::string::npos);
}

// DDS Security: the folder of deploy/security/make_certs.sh gives Cyclone's three plugins their
// files; a missing file is named, and the participant is not made without it.
TEST(ParticipantConfig, SecurityFolderGivesThePluginsItsFilesAndAMissingOneIsNamed) {
    char tmpl[] = "/tmp/df_security_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    ParticipantConfig c;
    c.security_dir = dir;
    c.security_identity = "a";
    for (const char* f : {"identity_ca.pem", "permissions_ca.pem", "governance.p7s",
                          "permissions.p7s", "a.pem"}) {
        std::FILE* out = std::fopen((dir + "/" + f).c_str(), "w");
        ASSERT_NE(out, nullptr);
        std::fclose(out);
    }
    auto missing = domain_xml(c, true);
    ASSERT_FALSE(missing.is_ok());
    EXPECT_NE(missing.status().message().find(dir + "/a.key"), std::string::npos)
        << missing.status().message();
    std::FILE* key = std::fopen((dir + "/a.key").c_str(), "w");
    ASSERT_NE(key, nullptr);
    std::fclose(key);
    auto xml = domain_xml(c, true);
    ASSERT_TRUE(xml.is_ok()) << xml.status().message();
    for (const std::string part :
         {std::string(kSecurityPluginDir) + "/libdds_security_auth.so",
          std::string(kSecurityPluginDir) + "/libdds_security_ac.so",
          std::string(kSecurityPluginDir) + "/libdds_security_crypto.so",
          "<IdentityCertificate>file:" + dir + "/a.pem</IdentityCertificate>",
          "<PrivateKey>file:" + dir + "/a.key</PrivateKey>",
          "<Governance>file:" + dir + "/governance.p7s</Governance>",
          "<Permissions>file:" + dir + "/permissions.p7s</Permissions>"}) {
        EXPECT_NE(xml->find(part), std::string::npos) << part << " not in " << *xml;
    }
    ParticipantConfig no_identity = c;
    no_identity.security_identity = "";
    auto refused = domain_xml(no_identity, false);
    ASSERT_FALSE(refused.is_ok());
    EXPECT_NE(refused.status().message().find("security_identity"), std::string::npos);
    ParticipantConfig injected = c;
    injected.security_dir = dir + "\"/><x";
    EXPECT_FALSE(domain_xml(injected, false).is_ok());
    EXPECT_EQ(domain_xml(ParticipantConfig{}, false)->find("Security"), std::string::npos)
        << "off by default";
    for (const char* f : {"identity_ca.pem", "permissions_ca.pem", "governance.p7s",
                          "permissions.p7s", "a.pem", "a.key"}) {
        std::remove((dir + "/" + f).c_str());
    }
    rmdir(tmpl);
}

}  // namespace
}  // namespace df::dds
