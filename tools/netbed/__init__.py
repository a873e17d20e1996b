"""netbed: a two-host network test bed on one machine (network namespaces and a user-space
forwarder with delay, jitter, loss and cuts), for RoboPuppet's two-host tests.

Modules: bed (the Bed class: up, down, set, cut, restore, exec; the nftables loader),
forwarder (runs in the bed's network namespace), impairment (the pure per-direction scheduler),
netns (namespace primitives), cli (the `tools/netbed/netbed` command). Import with the folder
that holds netbed/ (tools/) on sys.path: `from netbed.bed import Bed`.
"""
