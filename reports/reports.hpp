#pragma once
// reports — per-fabric and per-family error tables and plots (SPEC §1 step 5, §3 "Error
// metrics reported"). No code yet.
namespace yarnfit::reports {}
