% expect: shell/1 is not allowed in a mission
mission.
:- if(shell('touch marker')).
:- endif.
