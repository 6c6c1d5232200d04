"""From the policy's action to joint targets: the joint-target filters (filters), the central pattern
generator (cpg) and the approaches that combine them into action pipelines, with their registry (actions). It may
import protocol and below."""
