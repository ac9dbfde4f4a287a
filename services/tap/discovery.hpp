#pragma once
/// What is on the bus: topics with their types, writers and readers, and the hosts and
/// processes behind them (Cyclone's built-in DCPSParticipant/Publication/Subscription topics).
#include <map>
#include <string>
#include <vector>

#include "dds/participant.hpp"

namespace df::tap {

struct EndpointInfo {
    std::string host;     ///< participant's __Hostname
    std::string process;  ///< __ProcessName (__Pid)
};

struct TopicInfo {
    std::string name;
    std::string type;
    std::vector<EndpointInfo> writers;
    std::vector<EndpointInfo> readers;
};

/// Listens for wait_s seconds and returns every topic seen (excluding this process's own).
std::map<std::string, TopicInfo> discover(const dds::Participant& participant, double wait_s);

/// Waits up to wait_s for a writer of topic; returns its type name.
Result<std::string> find_topic_type(const dds::Participant& participant, const std::string& topic,
                                    double wait_s);

}  // namespace df::tap
