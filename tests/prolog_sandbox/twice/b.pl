p.
:- system:include('/etc/hostname').
