"""The control: the pointing loop, exact norms, worst-case bounds and the robust structured synthesis of the PMA gain.

``closedloop`` (the pointing study's generalized plant), ``hinf`` (exact H-infinity norms), ``mu`` and ``mu_interval``
(worst-case gain bounds, pointwise and certified over frequency intervals), ``synthesis`` (robust structured
synthesis) and ``modalloop`` (the synthesis's fast path).

It imports the model (:mod:`trusscodesign.model`) and the plumbing only.
"""
